/*
 * charges.h — the master's own work on the results, charged to its
 * simulated host (sim/tile_run.c): sim/main.c hands these to the real
 * master as its master_costs (host/master.h).
 */
#ifndef SIM_CHARGES_H
#define SIM_CHARGES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The master's own work on the results, executed on its simulated host
 * as measured on a real master (bench/simulate.sh --master-message-us,
 * --master-part-us, --master-pixel-ns, --master-store-ns; bench/SCALE.md);
 * each 0 when unset, which leaves the master only MPI's per-message costs.
 * A RESULT message: $CSGSIM_MASTER_MESSAGE_S seconds.  A part of `pixels`
 * pixels: $CSGSIM_MASTER_PART_S + pixels x $CSGSIM_MASTER_PIXEL_S (checking
 * it, counting it, queuing its tile for the journal; with the store thread,
 * copying its bytes into the ring).  With $CSGSIM_MASTER_STORE_S, an 8-bit
 * (`rgb8`) part's pixels are stored by the store thread (host/store.h), a
 * core of its own at that many seconds a pixel: queued while the ring has
 * room for them behind what the thread has not stored yet, else stored by
 * the loop itself at that cost.  A compressed part (PIXELS_RGB8Z) is first
 * decompressed by the store thread, as the real one does (a real render
 * to an 8-bit file has one): $CSGSIM_MASTER_DECOMPRESS_S seconds a byte
 * of its 3 x pixels (bench/compress_tiles.c measures it) more on the
 * thread, or on the loop when every ring is full; it takes its
 * `compressed` bytes in the ring. */
void sim_charge_master_message(void);
void sim_charge_master_part(size_t pixels, int format, size_t compressed);
/* The store threads the charges model ($CSGSIM_MASTER_STORE_THREADS, or
 * --store-threads auto's for $CSGSIM_WORKERS workers when it is unset or
 * 0). */
int sim_master_store_threads(void);
/* The end of the tile phase: waits until the store thread has stored
 * everything queued (master_run_tiles). */
void sim_master_store_drain(void);
/* Pages packed for a worker's request (--scene-memory): bytes x
 * $CSGSIM_MASTER_PAGE_S (seconds a byte; 0 when unset). */
void sim_charge_master_pages(uint64_t bytes);
/* A home worker's answer to another's page ask: its packing, at rank 0's
 * rate ($CSGSIM_MASTER_PAGE_S), on the worker's host. */
void sim_charge_worker_serve(uint64_t bytes);

#endif
