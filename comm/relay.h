/*
 * relay.h — a relay rank: the master of one group of workers, one worker
 * to rank 0 (--relays, comm/protocol.h).
 *
 * With hundreds of workers the single master's messages bound the render
 * (bench/SCALE.md: at 256 workers ~10 us of MPI overhead a message, two
 * messages an item).  A relay takes rank 0's TILEs, large batches of
 * items since rank 0 sizes them for a group (schedule.h's guided share
 * over K relays, not over every worker), deals their parts to its
 * workers kept PROTO_IN_FLIGHT messages deep (the same protocol as rank
 * 0's), gathers the answers, and answers each TILE of rank 0 with one
 * RESULT, in order, its parts naming the worker that computed each.  Rank
 * 0 then handles one message pair per batch of the group instead of one
 * per worker message.
 *
 * A relay never decides what is rendered: order, batch sizes and the
 * image stay rank 0's; the pixels pass through unchanged, so an image is
 * the same bit for bit with and without relays.  Liveness stays rank 0's
 * (it watches every process): a relay whose worker dies is lost with its
 * group, and a relay exits when rank 0 is gone (its watchdog).
 */
#ifndef COMM_RELAY_H
#define COMM_RELAY_H

#include <stddef.h>

#include "mpi_link.h"
#include "protocol.h"

/* Rank `rank` (1 .. setup->relays), once the setup and its blob were
 * received and checked (scene->bytes NULL, scene->valid false or `failure`
 * non-empty: it cannot work): greets its group, then relays until rank
 * 0's STOP, whose status it returns after passing it on. */
int relay_run(int rank, const proto_setup *setup, const link_scene *scene, const char *failure);

#endif
