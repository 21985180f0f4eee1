/* The "state" object of a saved scene (io/scene_state.h): the snapshot as base64, with the
 * capacities the world restored into must have. */
#include "io/scene_state.h"
#include "core/error.h"
#include "kgyro/snapshot.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* const kStateFields[] = {"version", "max_bodies", "max_applicators", "snapshot", NULL};
static const char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/* ---- base64 ---- */

static char* kg_base64_encode(const unsigned char* data, size_t size)
{
    char* out = malloc(4 * ((size + 2) / 3) + 1);
    if (!out) {
        return NULL;
    }
    size_t at = 0;
    for (size_t i = 0; i < size; i += 3) {
        unsigned long v = (unsigned long)data[i] << 16;
        v |= i + 1 < size ? (unsigned long)data[i + 1] << 8 : 0u;
        v |= i + 2 < size ? (unsigned long)data[i + 2] : 0u;
        out[at++] = kBase64[(v >> 18) & 63u];
        out[at++] = kBase64[(v >> 12) & 63u];
        out[at++] = i + 1 < size ? kBase64[(v >> 6) & 63u] : '=';
        out[at++] = i + 2 < size ? kBase64[v & 63u] : '=';
    }
    out[at] = '\0';
    return out;
}

static int kg_base64_value(char c)
{
    const char* p = c ? strchr(kBase64, c) : NULL;
    return p ? (int)(p - kBase64) : -1;
}

/* Decodes text (a multiple of 4 characters, at most two '=' of padding at its end) into
 * *out (malloc'ed); 0 when it is not base64 or out of memory. */
static int kg_base64_decode(const char* text, unsigned char** out, size_t* size)
{
    size_t n = strlen(text);
    size_t pad = n >= 1 && text[n - 1] == '=' ? (n >= 2 && text[n - 2] == '=' ? 2u : 1u) : 0u;
    unsigned char* bytes = n % 4 == 0 ? malloc(n / 4 * 3 + 1) : NULL;
    if (!bytes) {
        return 0;
    }
    size_t at = 0;
    for (size_t i = 0; i < n; i += 4) {
        unsigned long word = 0;
        for (size_t k = 0; k < 4; ++k) {
            int padding = i + k >= n - pad;
            int v = padding ? 0 : kg_base64_value(text[i + k]);
            if (v < 0) {
                free(bytes);
                return 0;
            }
            word = (word << 6) | (unsigned long)v;
        }
        size_t keep = i + 4 == n ? 3u - pad : 3u;
        for (size_t k = 0; k < keep; ++k) {
            bytes[at++] = (unsigned char)(word >> (16u - 8u * k));
        }
    }
    *out = bytes;
    *size = at;
    return 1;
}

/* ---- reading ---- */

/* Whether the snapshot restores into a world of the scene's definition and holds the
 * scene's bodies: tried on a world of the CPU backend, so that a scene the loader
 * accepts instantiates (the fuzz targets' contract). */
static kg_result kg_check_state_fits(const kg_scene* scene, const void* bytes, size_t size,
                                     const kg_json_reader* reader, const kg_json_path* at)
{
    kg_world_def def = *kg_scene_world_def((kg_scene*)scene);
    def.backend = KG_BACKEND_CPU;
    def.threads = 1;
    kg_world* world = NULL;
    kg_result r = kg_create_world(&def, &world);
    if (r == KG_OK) {
        r = kg_world_restore(world, bytes, size);
    }
    char reason[384];
    snprintf(reason, sizeof reason, "%s", kg_last_error());
    int bodies = r == KG_OK ? kg_world_body_count(world) : 0;
    kg_destroy_world(world);
    if (r == KG_OK && bodies != kg_scene_body_count(scene)) {
        return kg_json_fail(reader, at, "the snapshot holds %d bodies, the scene %d", bodies,
                            kg_scene_body_count(scene));
    }
    if (r == KG_ERROR_OUT_OF_MEMORY) {
        return kg_json_fail_message(r, "%s: %s", reader->source, reason);
    }
    return r == KG_OK ? KG_OK : kg_json_fail(reader, at, "%s", reason);
}

kg_result kg_read_scene_state(kg_scene* scene, const cJSON* root, const kg_json_reader* reader)
{
    const cJSON* state = cJSON_GetObjectItemCaseSensitive(root, "state");
    if (!state) {
        return KG_OK;
    }
    kg_json_path root_path = {""};
    kg_json_path path = kg_json_path_key(&root_path, "state");
    KG_TRY(kg_json_check_object(reader, state, &path, kStateFields));
    int version = 0;
    kg_world_def* def = kg_scene_world_def(scene);
    KG_TRY(kg_json_require(reader, state, &path, "version"));
    KG_TRY(kg_json_int(reader, state, &path, "version", 0, 1 << 30, &version));
    if ((unsigned)version != KG_SNAPSHOT_VERSION) {
        kg_json_path at = kg_json_path_key(&path, "version");
        return kg_json_fail(reader, &at, "snapshot format version %d: this build reads version %u only", version,
                            KG_SNAPSHOT_VERSION);
    }
    KG_TRY(kg_json_require(reader, state, &path, "max_bodies"));
    KG_TRY(kg_json_int(reader, state, &path, "max_bodies", 1, 1 << 26, &def->max_bodies));
    KG_TRY(kg_json_int(reader, state, &path, "max_applicators", 0, 1 << 20, &def->max_applicators));
    KG_TRY(kg_json_require(reader, state, &path, "snapshot"));
    const cJSON* text = cJSON_GetObjectItemCaseSensitive(state, "snapshot");
    kg_json_path at = kg_json_path_key(&path, "snapshot");
    unsigned char* bytes = NULL;
    size_t size = 0;
    if (!cJSON_IsString(text) || !kg_base64_decode(text->valuestring, &bytes, &size)) {
        return kg_json_fail(reader, &at, "must be a string of base64 (a snapshot written by kg_scene_save_file)");
    }
    kg_result r = kg_check_state_fits(scene, bytes, size, reader, &at);
    if (r == KG_OK) {
        r = kg_scene_set_state(scene, bytes, size);
    }
    free(bytes);
    return r;
}

/* ---- writing ---- */

cJSON* kg_scene_state_json(const kg_scene* scene)
{
    size_t size = 0;
    const void* snapshot = kg_scene_get_state(scene, &size);
    char* text = snapshot ? kg_base64_encode(snapshot, size) : NULL;
    cJSON* state = text ? cJSON_CreateObject() : NULL;
    const kg_world_def* def = kg_scene_world_def((kg_scene*)scene);
    if (state && (!cJSON_AddNumberToObject(state, "version", KG_SNAPSHOT_VERSION) ||
                  !cJSON_AddNumberToObject(state, "max_bodies", def->max_bodies) ||
                  !cJSON_AddNumberToObject(state, "max_applicators", def->max_applicators) ||
                  !cJSON_AddStringToObject(state, "snapshot", text))) {
        cJSON_Delete(state);
        state = NULL;
    }
    free(text);
    return state;
}

/* ---- restoring ---- */

/* Sets body's pose and velocities to the scene's def where they differ from the world's. */
static kg_result kg_apply_edit(kg_world* world, kg_body body, const kg_body_def* d)
{
    kg_body_state s;
    KG_TRY(kg_body_get_state(world, body, &s));
    if (memcmp(&s.position, &d->position, sizeof s.position) != 0 || memcmp(&s.angle, &d->angle, sizeof s.angle) != 0) {
        KG_TRY(kg_body_set_transform(world, body, d->position, d->angle));
    }
    if (memcmp(&s.velocity, &d->velocity, sizeof s.velocity) != 0) {
        KG_TRY(kg_body_set_velocity(world, body, d->velocity));
    }
    if (memcmp(&s.angular_velocity, &d->angular_velocity, sizeof s.angular_velocity) != 0) {
        KG_TRY(kg_body_set_angular_velocity(world, body, d->angular_velocity));
    }
    return KG_OK;
}

kg_result kg_scene_restore_state(const kg_scene* scene, kg_world* world, kg_body* handles)
{
    size_t size = 0;
    const void* snapshot = kg_scene_get_state(scene, &size);
    if (!snapshot) {
        return KG_OK;
    }
    if (kg_world_restore(world, snapshot, size) != KG_OK) {
        char reason[384];
        snprintf(reason, sizeof reason, "%s", kg_last_error());
        return kg_fail(KG_ERROR_PARSE, "state.snapshot: %s", reason);
    }
    int count = kg_scene_body_count(scene), live = 0;
    if (kg_world_body_count(world) != count) {
        return kg_fail(KG_ERROR_PARSE, "state.snapshot: it holds %d bodies, the scene %d", kg_world_body_count(world),
                       count);
    }
    KG_TRY(kg_world_get_bodies(world, handles, count, &live));
    for (int i = 0; i < count; ++i) {
        KG_TRY(kg_apply_edit(world, handles[i], kg_scene_body_def(scene, i)));
    }
    return KG_OK;
}
