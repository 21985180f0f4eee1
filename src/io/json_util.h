/* Strict JSON reading for the loaders. Every accessor checks the type and range of one
 * field; on failure it sets kg_last_error() to "SOURCE: PATH: what is wrong" and returns
 * KG_ERROR_PARSE, so a loader is a chain of KG_TRY(...) calls and every message names
 * the file and the JSON path of the offending value. */
#ifndef KG_JSON_UTIL_H
#define KG_JSON_UTIL_H

#include "core/error.h"
#include "kgyro/types.h"

#include <cjson/cJSON.h>
#include <stdint.h>

/* The most points a chain of a scene file or a Tiled map may have (a terrain outline of
 * 100 km at one point a metre): larger is a broken or hostile file. */
#define KG_MAX_CHAIN_POINTS 100000

/* The most entries of a body's "shapes" in a scene file (read and written). */
#define KG_SCENE_MAX_SHAPES 64

/* A JSON path such as "bodies[3].shape.radius"; "" is the document itself. */
typedef struct kg_json_path {
    char text[192];
} kg_json_path;

kg_json_path kg_json_path_key(const kg_json_path* parent, const char* key);
kg_json_path kg_json_path_index(const kg_json_path* parent, int index);

/* What a number must satisfy; each has its own message ("must be > 0"...). */
typedef enum kg_json_rule {
    KG_JSON_ANY,          /* finite */
    KG_JSON_POSITIVE,     /* > 0 */
    KG_JSON_NON_NEGATIVE, /* >= 0 */
    KG_JSON_UNIT          /* in [0, 1] */
} kg_json_rule;

typedef struct kg_json_reader {
    const char* source; /* the file name the messages start with */
} kg_json_reader;

/* Copies text to out (size bytes, NUL-terminated), each control character and each byte
 * of invalid UTF-8 turned into '?': names, keys and paths a file gives are echoed in
 * messages through this (kg_json_fail and the file errors below do it), so that a
 * hostile file cannot send escape sequences to a terminal or break a log's encoding. */
void kg_json_clean_text(char* out, size_t size, const char* text);

/* The message of what f breaks of rule ("must be > 0"...; not finite breaks every rule),
 * NULL when it keeps it. */
const char* kg_json_rule_broken(float f, kg_json_rule rule);

kg_result kg_json_fail(const kg_json_reader* reader, const kg_json_path* path, const char* fmt, ...)
    KG_PRINTF(3, 4);
/* A failure with no JSON path (a file that cannot be read, out of memory): the message,
 * which names a file, cleaned as kg_json_fail's. */
kg_result kg_json_fail_message(kg_result code, const char* fmt, ...) KG_PRINTF(2, 3);

/* Reads the whole regular file at path, of at most max_bytes, into *out (free() it) and
 * its length into *length. Anything else (a FIFO, a device, a directory) is refused at
 * once, before a byte is read, so that a hostile path can neither block the loader nor
 * feed it without end; so is a file larger than max_bytes. Fails with KG_ERROR_IO and
 * "PATH: what is wrong". */
kg_result kg_json_read_file(const char* path, size_t max_bytes, char** out, size_t* length);

/* Parses a whole document. Syntax errors read "SOURCE: line L, column C: ...". */
kg_result kg_json_parse(const kg_json_reader* reader, const char* text, size_t length, cJSON** out);

/* Checks that value is an object whose keys are all in allowed (a NULL-terminated list)
 * and none is repeated. */
kg_result kg_json_check_object(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                               const char* const* allowed);
kg_result kg_json_check_array(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path);
/* Fails with "is required" when object has no field key. */
kg_result kg_json_require(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                          const char* key);

/* Optional fields: an absent key leaves *out unchanged (the default). */
kg_result kg_json_float(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                        const char* key, kg_json_rule rule, float* out);
kg_result kg_json_vec2(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                       const char* key, kg_vec2* out);
/* An integer in [min, max]. */
kg_result kg_json_int(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                      const char* key, int min, int max, int* out);
kg_result kg_json_uint32(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                         const char* key, uint32_t* out);
kg_result kg_json_bool(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                       const char* key, int* out);
/* *out points into the document (valid while it lives). */
kg_result kg_json_string(const kg_json_reader* reader, const cJSON* object, const kg_json_path* path,
                         const char* key, const char** out);

/* Reads an array element [x, y] (value itself, not a field). */
kg_result kg_json_vec2_value(const kg_json_reader* reader, const cJSON* value, const kg_json_path* path,
                             kg_vec2* out);

/* Writing (kg_scene_save_file): a float as "%.9g", which reads back as the same float
 * (9 significant digits tell any two floats apart), and [x, y] of two; NULL when out of
 * memory or a value is not finite (JSON has no NaN or infinity). */
cJSON* kg_float_json(float v);
cJSON* kg_vec2_json(kg_vec2 v);
/* Adds key: item to object; 0 when item is NULL (out of memory) or it cannot. */
int kg_json_add(cJSON* object, const char* key, cJSON* item);
int kg_json_add_float(cJSON* object, const char* key, float v);
int kg_json_add_vec2(cJSON* object, const char* key, kg_vec2 v);

#endif
