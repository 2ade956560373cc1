/*
 * compare.h — `csgtrace compare`: homo then hetero on the same scene in
 * one MPI job, the images checked bit for bit, one table.
 */
#ifndef HOST_COMPARE_H
#define HOST_COMPARE_H

#include "cli.h"

/* Every rank calls it with the same arguments; returns the exit status
 * (1 when the two images differ). */
int compare_run(const cli_args *a);

#endif
