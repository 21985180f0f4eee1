#ifdef KG_HAVE_OPENCL
#include "backend/opencl/cl_fault.h"
#include "core/error.h"

#include <stdlib.h>
#include <string.h>

static const char* const kSiteNames[KG_CL_FAULT_SITE_COUNT] = {"load",  "platform", "build", "alloc",
                                                               "enqueue", "finish", "read", "lost"};

static int kg_site_of(const char* name, size_t length)
{
    for (int s = 0; s < KG_CL_FAULT_SITE_COUNT; ++s) {
        if (strlen(kSiteNames[s]) == length && strncmp(kSiteNames[s], name, length) == 0) {
            return s;
        }
    }
    return -1;
}

void kg_cl_faults_from_env(kg_cl_faults* faults)
{
    memset(faults, 0, sizeof *faults);
    const char* spec = getenv("KGYRO_CL_FAIL");
    while (spec && *spec) {
        size_t length = strcspn(spec, ",");
        size_t name_length = strcspn(spec, ":,");
        int site = kg_site_of(spec, name_length);
        int nth = name_length < length ? atoi(spec + name_length + 1) : 1;
        if (site < 0 || nth < 1) {
            kg_warn_once("cl-fail-spec", "KGYRO_CL_FAIL: ignoring '%.*s' (expected site[:N] with site one of "
                         "load, platform, build, alloc, enqueue, finish, read, lost)", (int)length, spec);
        } else {
            faults->fail_at[site] = nth;
        }
        spec += length + (spec[length] == ',');
    }
}

int kg_cl_fault(kg_cl_faults* faults, kg_cl_fault_site site)
{
    if (site == KG_CL_FAULT_ENQUEUE && faults->fail_at[KG_CL_FAULT_LOST] &&
        ++faults->calls[KG_CL_FAULT_LOST] >= faults->fail_at[KG_CL_FAULT_LOST]) {
        faults->lost = 1;
    }
    if (faults->lost && (site == KG_CL_FAULT_ENQUEUE || site == KG_CL_FAULT_FINISH || site == KG_CL_FAULT_READ)) {
        return 1;
    }
    return faults->fail_at[site] != 0 && ++faults->calls[site] == faults->fail_at[site];
}
#endif
