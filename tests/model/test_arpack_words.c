/* test_arpack_words.c - ARPACK's info codes in words (vi_arpack_words,
 * internal to vi_eigs.c, reached through the static archive).  The codes
 * other than 1 cannot be provoked through vi_sparse.h (the library passes
 * ARPACK valid arguments and a nonzero start vector; test_sparse provokes
 * info 1), so the words are checked against ARPACK's documentation of
 * dsaupd and dseupd, which number some errors differently: -12 is the
 * shift strategy for dsaupd but nev = 1 with which = BE for dseupd, which
 * dsaupd calls -13; -14..-17 are dseupd's alone, -9999 dsaupd's. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "vi_fe_internal.h"

#define assert_words(eupd, info, s) \
  assert_non_null(strstr(vi_arpack_words((eupd), (info)), (s)))

static void test_dsaupd(void **state)
{
  (void)state;
  assert_words(0, 1, "maximum number of iterations");
  assert_words(0, 3, "no shifts could be applied");
  assert_words(0, -1, "n must be positive");
  assert_words(0, -3, "ncv must exceed");
  assert_words(0, -7, "workl is too short");
  assert_words(0, -8, "dsteqr");
  assert_words(0, -9, "starting vector is zero");
  assert_words(0, -12, "iparam(1) must be 0 or 1");
  assert_words(0, -13, "which = BE");
  assert_words(0, -9999, "could not build a Lanczos (Arnoldi) factorisation");
  /* dseupd's own codes are unknown to dsaupd */
  assert_words(0, -14, "an unknown code");
  assert_words(0, -17, "an unknown code");
  assert_words(0, 2, "an unknown code");
}

static void test_dseupd(void **state)
{
  (void)state;
  assert_words(1, -9, "starting vector is zero");
  assert_words(1, -12, "which = BE");
  assert_words(1, -14, "no eigenvalue to sufficient accuracy");
  assert_words(1, -15, "howmny must be A or S");
  assert_words(1, -16, "howmny = S is not implemented");
  assert_words(1, -17, "other converged Ritz values than dsaupd");
  assert_words(1, -13, "an unknown code");
  assert_words(1, -9999, "an unknown code");
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_dsaupd),
      cmocka_unit_test(test_dseupd),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
