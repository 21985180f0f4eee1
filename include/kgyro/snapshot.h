/* KineticGyro: snapshots of a world's whole simulation state, for rollback, replays and
 * save games, in a buffer the caller owns.
 *
 *   size_t size = 0, written = 0;
 *   kg_world_snapshot_size(world, &size);
 *   void* buffer = malloc(size);
 *   kg_world_snapshot(world, buffer, size, &written);
 *   ... steps ...
 *   kg_world_restore(world, buffer, written);   // back to the state of the snapshot
 *
 * Stepping a restored world gives bitwise the states the world had when it was stepped
 * from the snapshot the first time: on either backend, with any thread count.
 *
 * What a snapshot holds: bodies and shapes (state, properties, sleep timers and islands),
 * the contacts with their warm-start impulses and colours, tile maps with their edits and
 * the one-way platform state, the joints (their rows with the warm-start impulses, and
 * every slot's generation), the built-in force applicators (gravity, wind) with their
 * body lists, the step counter, gravity and the other simulation settings of
 * kg_world_def, and every handle generation and free slot (handles of the world the
 * snapshot was taken of are valid in the restored world; see below). Caches the step
 * rebuilds (broadphase pairs, query index, continuous collision's lists) are not saved:
 * they are rebuilt, to the same bits.
 *
 * What it does not hold (docs/design.md, "Snapshots"):
 *  - callbacks: user force applicators (kg_add_force_applicator, device forces) and the
 *    pre-solve callback are the restored world's own. A snapshot's user applicators are
 *    matched by slot: the world restored into must have a user applicator in exactly the
 *    slots the snapshot has one (register them in the same order); each keeps its
 *    function and user data, and takes the snapshot's handle generation and body list.
 *  - user data pointers of bodies and shapes are saved as values: restored as they were,
 *    which is right within one process (rollback); a snapshot read by another process
 *    must set them again.
 *  - contact events and sensor events of the step before the snapshot: after a restore
 *    the first step reports its events against the restored contacts (contact events), or
 *    as if the sensors were new (every overlap begins).
 *
 * Handles across worlds. A snapshot carries the identity of the world it was taken of:
 * restoring it makes the world that one, generations and world tag included
 * (core/generation.h), so the handles of the snapshot's world are valid in the restored
 * world and the restored world's own earlier handles are not (unless the snapshot came
 * from the same world). A fresh world restored from another world's snapshot thus shares
 * that world's tag: handles of one are valid in the other while both name live slots
 * alike.
 *
 * The world restored into must be compatible: the same max_bodies and max_applicators,
 * and a user applicator in the same slots. Its backend, device and thread count are its
 * own (a snapshot is backend-independent); every other kg_world_def setting comes from
 * the snapshot.
 *
 * Format: a header (magic "KGYROSNP", format version, the layout fingerprint: byte order,
 * sizeof(float), of a pointer and of each pooled struct, total size, checksum) and the
 * state in native byte order. A snapshot is only read by a build with the same version
 * and layout. A buffer that is not a snapshot, of another version or layout, truncated
 * or corrupted (checksum), or whose contents do not fit together, is refused with
 * KG_ERROR_INVALID_ARGUMENT (KG_ERROR_UNSUPPORTED for another version or layout) and a
 * message that says why; the world is then left exactly as it was. */
#ifndef KGYRO_SNAPSHOT_H
#define KGYRO_SNAPSHOT_H

#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The format version this build writes and reads. */
#define KG_SNAPSHOT_VERSION 2u

/* The bytes kg_world_snapshot would write now (they change as the world does). */
KG_API kg_result kg_world_snapshot_size(const kg_world* world, size_t* bytes);

/* Writes the world's state into buffer (capacity bytes, any alignment); *written gets
 * its size. A buffer too small is KG_ERROR_INVALID_ARGUMENT, *written then the size
 * needed, and nothing is written. Refused inside kg_world_step's callbacks
 * (KG_ERROR_LOCKED). On the OpenCL backend the state arrays, contacts and one-way state
 * are read back from the device (nothing else). */
KG_API kg_result kg_world_snapshot(kg_world* world, void* buffer, size_t capacity, size_t* written);

/* Replaces the world's state by the snapshot's (size bytes, as written). On any error the
 * world is unchanged. Refused inside kg_world_step's callbacks (KG_ERROR_LOCKED). On the
 * OpenCL backend the state is uploaded before the next step. */
KG_API kg_result kg_world_restore(kg_world* world, const void* buffer, size_t size);

#ifdef __cplusplus
}
#endif
#endif
