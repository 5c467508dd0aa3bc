/* For the lint only (tests/checks/lint_test.sh force-includes it into the
 * test files that use cmocka; nothing compiles it): tells clang's
 * path-sensitive analyser that a failed cmocka assertion ends the test.
 * cmocka 1.1 leaves by longjmp from an ordinary function, which the
 * analyser cannot see, so it went on along every path on which an
 * assertion had failed: paths no test runs, explored for nothing (half of
 * test_writer.c's analysis), and facts the assertion establishes (a
 * pointer not NULL, an index equal to a bound) not known after it.  The
 * expressions are evaluated once, with cmocka's own casts. */
#ifndef VI_CMOCKA_ANALYZER_H
#define VI_CMOCKA_ANALYZER_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

void vi_lint_assert_failed(void) __attribute__((analyzer_noreturn));

#define VI_LINT_ASSERT(c)                \
  do {                                   \
    if (!(c)) vi_lint_assert_failed();   \
  } while (0)

#undef assert_true
#define assert_true(c) VI_LINT_ASSERT(cast_to_largest_integral_type(c))
#undef assert_false
#define assert_false(c) VI_LINT_ASSERT(!cast_to_largest_integral_type(c))
#undef assert_non_null
#define assert_non_null(c) VI_LINT_ASSERT((c) != NULL)
#undef assert_null
#define assert_null(c) VI_LINT_ASSERT((c) == NULL)
#undef assert_int_equal
#define assert_int_equal(a, b) \
  VI_LINT_ASSERT(cast_to_largest_integral_type(a) == cast_to_largest_integral_type(b))
#undef assert_int_not_equal
#define assert_int_not_equal(a, b) \
  VI_LINT_ASSERT(cast_to_largest_integral_type(a) != cast_to_largest_integral_type(b))
#undef fail
#define fail() vi_lint_assert_failed()
#undef fail_msg
#define fail_msg(...) vi_lint_assert_failed()

#endif
