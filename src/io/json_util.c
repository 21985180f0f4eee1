#include "io/json_util.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A path too long for its buffer ends in "..." rather than being cut silently. */
static void kg_json_mark_truncated(kg_json_path* path, int written)
{
    if (written < 0 || (size_t)written >= sizeof path->text) {
        memcpy(path->text + sizeof path->text - 4, "...", 4);
    }
}

kg_json_path kg_json_path_key(const kg_json_path* parent, const char* key)
{
    kg_json_path path;
    int written;
    if (parent->text[0] == '\0') {
        written = snprintf(path.text, sizeof path.text, "%s", key);
    } else {
        written = snprintf(path.text, sizeof path.text, "%s.%s", parent->text, key);
    }
    kg_json_mark_truncated(&path, written);
    return path;
}

kg_json_path kg_json_path_index(const kg_json_path* parent, int index)
{
    kg_json_path path;
    kg_json_mark_truncated(&path, snprintf(path.text, sizeof path.text, "%s[%d]", parent->text, index));
    return path;
}

/* The length of the UTF-8 sequence at s when it is valid and not a control character
 * (C0, DEL or C1), else 0. Overlong forms, surrogates and code points past U+10FFFF are
 * invalid. */
static size_t kg_printable_utf8_length(const unsigned char* s)
{
    static const unsigned kShortest[] = {0, 0, 0x80, 0x800, 0x10000};
    unsigned c = s[0];
    if (c >= 0x20 && c < 0x7f) {
        return 1;
    }
    size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    unsigned code = c & (0x7fu >> n);
    for (size_t i = 1; i < n; ++i) {
        if ((s[i] & 0xc0) != 0x80) {
            return 0; /* also stops at the terminating NUL */
        }
        code = (code << 6) | (s[i] & 0x3fu);
    }
    int valid = n > 0 && code >= kShortest[n] && code <= 0x10ffff && !(code >= 0xd800 && code <= 0xdfff);
    return valid && !(code >= 0x80 && code <= 0x9f) ? n : 0;
}

void kg_json_clean_text(char* out, size_t size, const char* text)
{
    const unsigned char* s = (const unsigned char*)text;
    size_t used = 0;
    while (*s && used + 1 < size) {
        size_t n = kg_printable_utf8_length(s);
        if (n == 0) {
            out[used++] = '?';
            s++;
        } else if (used + n < size) {
            memcpy(out + used, s, n);
            used += n;
            s += n;
        } else {
            break;
        }
    }
    out[used] = '\0';
}

kg_result kg_json_fail_message(kg_result code, const char* fmt, ...)
{
    char message[512];
    va_list args;
    va_start(args, fmt);
    vsnprintf(message, sizeof message, fmt, args);
    va_end(args);
    char clean[512];
    kg_json_clean_text(clean, sizeof clean, message);
    return kg_fail(code, "%s", clean);
}

kg_result kg_json_fail(const kg_json_reader* reader, const kg_json_path* path, const char* fmt, ...)
{
    char what[256];
    va_list args;
    va_start(args, fmt);
    vsnprintf(what, sizeof what, fmt, args);
    va_end(args);
    const char* where = path->text[0] != '\0' ? path->text : "(root)";
    return kg_json_fail_message(KG_ERROR_PARSE, "%s: %s: %s", reader->source, where, what);
}

/* Opens path for reading if it is a regular file of at most max_bytes. O_NONBLOCK: opening
 * a FIFO would otherwise wait for a writer. */
static kg_result kg_open_regular_file(const char* path, size_t max_bytes, int* out_fd, size_t* out_size)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0) {
        return kg_json_fail_message(KG_ERROR_IO, "%s: cannot open (%s)", path, strerror(errno));
    }
    struct stat info;
    if (fstat(fd, &info) != 0) {
        int error = errno;
        close(fd);
        return kg_json_fail_message(KG_ERROR_IO, "%s: cannot open (%s)", path, strerror(error));
    }
    if (!S_ISREG(info.st_mode)) {
        close(fd);
        return kg_json_fail_message(KG_ERROR_IO, "%s: not a regular file (a %s)", path,
                       S_ISDIR(info.st_mode) ? "directory" : S_ISFIFO(info.st_mode) ? "FIFO" : "device or socket");
    }
    if ((uintmax_t)info.st_size > (uintmax_t)max_bytes) {
        close(fd);
        return kg_json_fail_message(KG_ERROR_IO, "%s: larger than the limit of %zu bytes", path, max_bytes);
    }
    *out_fd = fd;
    *out_size = (size_t)info.st_size;
    return KG_OK;
}

kg_result kg_json_read_file(const char* path, size_t max_bytes, char** out, size_t* length)
{
    int fd = -1;
    size_t size = 0;
    KG_TRY(kg_open_regular_file(path, max_bytes, &fd, &size));
    char* text = malloc(size > 0 ? size : 1);
    size_t used = 0;
    int error = 0;
    while (text && used < size) {
        ssize_t got = read(fd, text + used, size - used);
        if (got <= 0) {
            error = got < 0 && errno != EINTR ? errno : 0;
            if (got == 0 || error != 0) {
                break; /* a file that shrank while read is taken as it is */
            }
            continue;
        }
        used += (size_t)got;
    }
    close(fd);
    if (!text || error != 0) {
        free(text);
        return kg_json_fail_message(KG_ERROR_IO, "%s: cannot read (%s)", path, text ? strerror(error) : "out of memory");
    }
    *out = text;
    *length = used;
    return KG_OK;
}

kg_result kg_json_parse(const kg_json_reader* reader, const char* text, size_t length, cJSON** out)
{
    const char* end = NULL;
    *out = cJSON_ParseWithLengthOpts(text, length, &end, 0);
    if (*out) {
        /* cJSON stops after the first value; anything but whitespace after it is an error */
        while (end < text + length && strchr(" \t\r\n", *end) != NULL && *end != '\0') {
            end++;
        }
        if (end == text + length) {
            return KG_OK;
        }
        cJSON_Delete(*out);
        *out = NULL;
    }
    if (!end || end < text || end > text + length) {
        end = text + length;
    }
    int line = 1, column = 1;
    for (const char* c = text; c < end; ++c) {
        if (*c == '\n') {
            line++;
            column = 1;
        } else {
            column++;
        }
    }
    /* Nothing of the text is quoted: a file that is not JSON at all may be a secret one
     * that a hostile level named (its first line would leak into the message). */
    const char* what = end == text + length ? "unexpected end of input" : "unexpected character";
    return kg_json_fail_message(KG_ERROR_PARSE, "%s: line %d, column %d: malformed JSON (%s)", reader->source, line, column,
                   what);
}

static int kg_json_allowed(const char* key, const char* const* allowed)
{
    for (int i = 0; allowed[i]; ++i) {
        if (strcmp(key, allowed[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

kg_result kg_json_check_object(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                               const char* const* allowed)
{
    if (!cJSON_IsObject(value)) {
        return kg_json_fail(reader, path, "must be an object");
    }
    for (const cJSON* field = value->child; field; field = field->next) {
        kg_json_path field_path = kg_json_path_key(path, field->string);
        if (!kg_json_allowed(field->string, allowed)) {
            return kg_json_fail(reader, &field_path, "unknown field");
        }
        /* cJSON keeps repeated keys; the later one would silently shadow the earlier */
        for (const cJSON* earlier = value->child; earlier != field; earlier = earlier->next) {
            if (strcmp(earlier->string, field->string) == 0) {
                return kg_json_fail(reader, &field_path, "field given twice");
            }
        }
    }
    return KG_OK;
}

kg_result kg_json_check_array(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path)
{
    return cJSON_IsArray(value) ? KG_OK : kg_json_fail(reader, path, "must be an array");
}

kg_result kg_json_require(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                          const char* key)
{
    if (cJSON_GetObjectItemCaseSensitive(object, key)) {
        return KG_OK;
    }
    kg_json_path field_path = kg_json_path_key(path, key);
    return kg_json_fail(reader, &field_path, "is required");
}

const char* kg_json_rule_broken(float f, kg_json_rule rule)
{
    if (!isfinite(f)) {
        return "must be a finite number";
    }
    switch (rule) {
    case KG_JSON_POSITIVE: return f > 0.0f ? NULL : "must be > 0";
    case KG_JSON_NON_NEGATIVE: return f >= 0.0f ? NULL : "must be >= 0";
    case KG_JSON_UNIT: return f >= 0.0f && f <= 1.0f ? NULL : "must be in [0, 1]";
    default: return NULL;
    }
}

static kg_result kg_json_number_value(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                                      kg_json_rule rule, float* out)
{
    if (!cJSON_IsNumber(value)) {
        return kg_json_fail(reader, path, "must be a number");
    }
    float f = (float)value->valuedouble;
    if (!isfinite(f)) {
        return kg_json_fail(reader, path, "must be a finite number (got %g)", value->valuedouble);
    }
    const char* broken = kg_json_rule_broken(f, rule);
    if (broken) {
        return kg_json_fail(reader, path, "%s", broken);
    }
    *out = f;
    return KG_OK;
}

kg_result kg_json_float(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                        const char* key, kg_json_rule rule, float* out)
{
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!value) {
        return KG_OK;
    }
    kg_json_path field_path = kg_json_path_key(path, key);
    return kg_json_number_value(reader, value, &field_path, rule, out);
}

kg_result kg_json_vec2_value(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                             kg_vec2* out)
{
    if (!cJSON_IsArray(value) || cJSON_GetArraySize(value) != 2) {
        return kg_json_fail(reader, path, "must be [x, y] (an array of two numbers)");
    }
    kg_vec2 v;
    kg_json_path x_path = kg_json_path_index(path, 0);
    kg_json_path y_path = kg_json_path_index(path, 1);
    KG_TRY(kg_json_number_value(reader, value->child, &x_path, KG_JSON_ANY, &v.x));
    KG_TRY(kg_json_number_value(reader, value->child->next, &y_path, KG_JSON_ANY, &v.y));
    *out = v;
    return KG_OK;
}

kg_result kg_json_vec2(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                       const char* key, kg_vec2* out)
{
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!value) {
        return KG_OK;
    }
    kg_json_path field_path = kg_json_path_key(path, key);
    return kg_json_vec2_value(reader, value, &field_path, out);
}

/* An integral number in [min, max]; doubles hold every 32-bit integer exactly. */
static kg_result kg_json_integer(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                                 const char* key, double min, double max, double* out)
{
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!value) {
        return KG_OK;
    }
    kg_json_path field_path = kg_json_path_key(path, key);
    double d = cJSON_IsNumber(value) ? value->valuedouble : NAN;
    if (!(d >= min && d <= max) || d != floor(d)) {
        return kg_json_fail(reader, &field_path, "must be an integer in [%.0f, %.0f]", min, max);
    }
    *out = d;
    return KG_OK;
}

kg_result kg_json_int(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                      const char* key, int min, int max, int* out)
{
    double d = *out;
    KG_TRY(kg_json_integer(reader, object, path, key, min, max, &d));
    *out = (int)d;
    return KG_OK;
}

kg_result kg_json_uint32(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                         const char* key, uint32_t* out)
{
    double d = *out;
    KG_TRY(kg_json_integer(reader, object, path, key, 0.0, 4294967295.0, &d));
    *out = (uint32_t)d;
    return KG_OK;
}

kg_result kg_json_bool(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                       const char* key, int* out)
{
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!value) {
        return KG_OK;
    }
    if (!cJSON_IsBool(value)) {
        kg_json_path field_path = kg_json_path_key(path, key);
        return kg_json_fail(reader, &field_path, "must be true or false");
    }
    *out = cJSON_IsTrue(value) ? 1 : 0;
    return KG_OK;
}

kg_result kg_json_string(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                         const char* key, const char** out)
{
    const cJSON* value = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!value) {
        return KG_OK;
    }
    if (!cJSON_IsString(value)) {
        kg_json_path field_path = kg_json_path_key(path, key);
        return kg_json_fail(reader, &field_path, "must be a string");
    }
    *out = value->valuestring;
    return KG_OK;
}

/* ---- writing ---- */

/* A float as "%.9g" (NULL: out of memory, or v not finite: JSON has no NaN or infinity,
 * and a bare "nan" would make the file unreadable). */
cJSON* kg_float_json(float v)
{
    if (!isfinite(v)) {
        return NULL;
    }
    char text[32];
    snprintf(text, sizeof text, "%.9g", (double)v);
    return cJSON_CreateRaw(text);
}

cJSON* kg_vec2_json(kg_vec2 v)
{
    cJSON* a = cJSON_CreateArray();
    if (a && (!cJSON_AddItemToArray(a, kg_float_json(v.x)) || !cJSON_AddItemToArray(a, kg_float_json(v.y)))) {
        cJSON_Delete(a);
        return NULL;
    }
    return a;
}

/* Adds key: item to object; 0 when item is NULL (out of memory) or cannot be added (then
 * deleted: the caller hands it over either way). */
int kg_json_add(cJSON* object, const char* key, cJSON* item)
{
    if (item && !cJSON_AddItemToObject(object, key, item)) {
        cJSON_Delete(item);
        return 0;
    }
    return item != NULL;
}

int kg_json_add_float(cJSON* object, const char* key, float v)
{
    return kg_json_add(object, key, kg_float_json(v));
}

int kg_json_add_vec2(cJSON* object, const char* key, kg_vec2 v)
{
    return kg_json_add(object, key, kg_vec2_json(v));
}
