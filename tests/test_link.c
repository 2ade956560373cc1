/*
 * test_link.c — where a worker computes (comm/mpi_link.h, link_worker_cpu):
 * bound to one CPU of its allowed set, by local rank, only when Open MPI
 * launched it unbound on a node with more ranks than allowed CPUs and
 * $CSGTRACE_WORKER_BIND is not "off"; left alone otherwise.
 */
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "../comm/mpi_link.h"

/* The set of CPUs first .. first + n - 1, every `step`-th. */
static cpu_set_t cpus(int first, int n, int step)
{
    cpu_set_t s;
    CPU_ZERO(&s);
    for (int i = 0; i < n; i++)
        CPU_SET(first + i * step, &s);
    return s;
}

static void test_oversubscribed_workers_spread(void **state)
{
    (void)state;
    cpu_set_t two = cpus(0, 2, 1);
    /* rank 0 (local 0) and two workers on 2 CPUs: the workers on 1 and 0 */
    assert_int_equal(link_worker_cpu(NULL, "none", "1", "3", &two), 1);
    assert_int_equal(link_worker_cpu(NULL, "none", "2", "3", &two), 0);
    /* four workers: round robin, two a CPU */
    assert_int_equal(link_worker_cpu(NULL, "none", "3", "5", &two), 1);
    assert_int_equal(link_worker_cpu(NULL, "none", "4", "5", &two), 0);
}

static void test_cpus_of_the_allowed_set(void **state)
{
    (void)state;
    cpu_set_t odd = cpus(1, 3, 2); /* 1, 3, 5 (a cpuset, a taskset) */
    assert_int_equal(link_worker_cpu(NULL, "none", "1", "5", &odd), 3);
    assert_int_equal(link_worker_cpu(NULL, "none", "2", "5", &odd), 5);
    assert_int_equal(link_worker_cpu(NULL, "none", "3", "5", &odd), 1);
    assert_int_equal(link_worker_cpu("on", "none", "4", "5", &odd), 3);
}

static void test_left_alone(void **state)
{
    (void)state;
    cpu_set_t two = cpus(0, 2, 1), eight = cpus(0, 8, 1), one = cpus(4, 1, 1);
    assert_int_equal(link_worker_cpu("off", "none", "1", "3", &two), -1);   /* asked    */
    assert_int_equal(link_worker_cpu(NULL, "core", "1", "3", &two), -1);    /* launcher */
    assert_int_equal(link_worker_cpu(NULL, NULL, "1", "3", &two), -1);      /* not ompi */
    assert_int_equal(link_worker_cpu(NULL, "none", NULL, "3", &two), -1);
    assert_int_equal(link_worker_cpu(NULL, "none", "1", NULL, &two), -1);
    assert_int_equal(link_worker_cpu(NULL, "none", "1", "2", &two), -1);    /* a core each */
    assert_int_equal(link_worker_cpu(NULL, "none", "2", "8", &eight), -1);
    assert_int_equal(link_worker_cpu(NULL, "none", "1", "3", &one), -1);    /* one CPU  */
    assert_int_equal(link_worker_cpu(NULL, "none", "-1", "3", &two), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_oversubscribed_workers_spread),
        cmocka_unit_test(test_cpus_of_the_allowed_set),
        cmocka_unit_test(test_left_alone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
