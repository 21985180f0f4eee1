#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_sources.h"

#include <string.h>

const kg_cl_source* kg_cl_find_source(const char* name)
{
    for (int i = 0; i < kg_cl_source_count; ++i) {
        if (strcmp(kg_cl_sources[i].name, name) == 0) {
            return &kg_cl_sources[i];
        }
    }
    return NULL;
}
#endif
