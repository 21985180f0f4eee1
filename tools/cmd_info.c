/* kgyro info: the backends this build has, and the OpenCL platforms and devices found,
 * with the limits that matter for choosing one (KGYRO_BACKEND=opencl:N, or
 * kg_world_def.device_index = N). */
#include "commands.h"
#include "kgyro/kgyro.h"
#include "kgyro/opencl.h"

#include <stdio.h>
#include <string.h>

static const char* kg_type_name(kg_opencl_device_type type)
{
    switch (type) {
    case KG_OPENCL_DEVICE_CPU: return "CPU";
    case KG_OPENCL_DEVICE_GPU: return "GPU";
    case KG_OPENCL_DEVICE_ACCELERATOR: return "accelerator";
    case KG_OPENCL_DEVICE_OTHER: break;
    }
    return "other";
}

static double kg_mib(uint64_t bytes) { return (double)bytes / (1024.0 * 1024.0); }

static void kg_print_device(const kg_opencl_device_info* d)
{
    printf("    device %d: %s (%s, %s)%s\n", d->index, d->name, kg_type_name(d->type), d->vendor,
           d->available ? "" : " [not available]");
    printf("      %s, driver %s\n", d->version, d->driver_version);
    printf("      %d compute units at %d MHz, max work-group %zu\n", d->compute_units, d->max_clock_mhz,
           d->max_work_group_size);
    printf("      memory %.0f MiB global, %.0f MiB per buffer, %.0f KiB local\n", kg_mib(d->global_memory),
           kg_mib(d->max_allocation), (double)d->local_memory / 1024.0);
    printf("      correctly rounded divide/sqrt: %s\n",
           d->correctly_rounded_divide_sqrt ? "yes (results bitwise equal to the CPU backend's)"
                                            : "no (results within rounding of the CPU backend's)");
}

static int kg_list_devices(void)
{
    int count = 0;
    kg_result r = kg_opencl_device_count(&count);
    if (r != KG_OK) {
        printf("  opencl   not usable: %s\n", kg_last_error());
        return 0;
    }
    printf("  opencl   %d device%s\n", count, count == 1 ? "" : "s");
    int platform = -1;
    for (int i = 0; i < count; ++i) {
        kg_opencl_device_info d;
        if (kg_opencl_get_device_info(i, &d) != KG_OK) {
            fprintf(stderr, "kgyro info: device %d: %s\n", i, kg_last_error());
            return 1;
        }
        if (d.platform_index != platform) {
            platform = d.platform_index;
            printf("  platform %d: %s (%s)\n", platform, d.platform_name, d.platform_version);
        }
        kg_print_device(&d);
    }
    return 0;
}

/* The backend a default world gets here, with KGYRO_BACKEND applied. */
static int kg_print_default_backend(void)
{
    kg_world_def def = kg_default_world_def();
    def.max_bodies = 1;
    kg_world* world = NULL;
    if (kg_create_world(&def, &world) != KG_OK) {
        fprintf(stderr, "kgyro info: cannot create a world: %s\n", kg_last_error());
        return 1;
    }
    printf("a default world (backend auto) runs on: %s\n",
           kg_world_backend(world) == KG_BACKEND_OPENCL ? "opencl" : "cpu");
    kg_destroy_world(world);
    return 0;
}

int kg_cmd_info(int argc, char** argv)
{
    if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        printf("usage: kgyro info\n\nLists the backends and the OpenCL platforms and devices found. A device is\n"
               "chosen with KGYRO_BACKEND=opencl:N (or kg_world_def.device_index = N with\n"
               "backend KG_BACKEND_OPENCL); auto takes the first GPU or accelerator.\n");
        return 0;
    }
    if (argc > 1) {
        fprintf(stderr, "kgyro info: unexpected argument '%s'\n", argv[1]);
        return 2;
    }
    printf("kgyro %d.%d.%d backends:\n  cpu      always\n", KGYRO_VERSION_MAJOR, KGYRO_VERSION_MINOR,
           KGYRO_VERSION_PATCH);
    if (kg_list_devices() != 0) {
        return 1;
    }
    return kg_print_default_backend();
}
