/* The rows four lanes wide: SSE2 on x86-64, NEON on ARM, GCC's generic vectors elsewhere. */
#include "solve/contact_wide.h"

#define KG_W 4
#include "solve/contact_vector_lanes.h"
#include "solve/contact_row.h"

#include "solve/contact_wide_impl.h"
