/* The kernel sources embedded at build time (see embed_kernels.cmake): per .cl file, its
 * text with every shared header it includes inlined, one string per line. */
#ifndef KG_CL_SOURCES_H
#define KG_CL_SOURCES_H

typedef struct kg_cl_source {
    const char* name; /* the .cl file's name without extension */
    const char* const* lines;
    int line_count;
} kg_cl_source;

extern const kg_cl_source kg_cl_sources[];
extern const int kg_cl_source_count;

/* The source called name, or NULL. */
const kg_cl_source* kg_cl_find_source(const char* name);

#endif
