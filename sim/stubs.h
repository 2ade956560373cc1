/*
 * stubs.h — the simulated build's link-time replacements (stubs.c).
 */
#ifndef SIM_STUBS_H
#define SIM_STUBS_H

#include <semaphore.h>

/* Sum the simulated naps of the wait on `wake` from now on. */
void sim_watch_naps(const sem_t *wake);
double sim_napped_s(void);

#endif
