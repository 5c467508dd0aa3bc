/* test_scene_edit.c - `--set KEY=VALUE` (vi_scene_edit): exactly one value
 * changes, everything else (comments, layout, line numbers) stays, and a
 * bad value is still reported at file:line of the key it overrides. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"

/* A comment with UTF-8 (Ω) before the values: libyaml's marks count
 * characters, the splice must count bytes. */
static const char *scene =
    "# Ω sweep test\n"                                  /* 1 */
    "name: t\n"                                         /* 2 */
    "model:\n"                                          /* 3 */
    "  chain: {n: 2, m: 1.0, k: 1.0, c: 0.1}\n"         /* 4 */
    "forcing: {omega: 0.9, a: [0.5, 0.0]}  # Ω = 0.9\n" /* 5 */
    "stop:\n"                                           /* 6 */
    "  mass: 2\n"                                       /* 7 */
    "  xs: 0.1\n"                                       /* 8 */
    "  r: 0.7\n"                                        /* 9 */
    "initial: {x: [0, 0], v: [0, 0]}\n";                /* 10 */

static vi_scene_edit *edit(void)
{
  vi_scene_edit *e = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_edit_create(scene, -1, "t.yaml", &e, &d), VI_OK);
  return e;
}

/* The text differs from the original only in the replaced span. */
static void one_value_changes(void **state)
{
  (void)state;
  vi_scene_edit *e = edit();
  vi_diag d;
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omega=1.25", &d), VI_OK);
  const char *t = vi_scene_edit_text(e), *p = strstr(scene, "0.9,");
  size_t pre = (size_t)(p - scene);
  assert_memory_equal(t, scene, pre);
  assert_memory_equal(t + pre, "1.25,", 5);
  assert_string_equal(t + pre + 4, scene + pre + 3);
  /* a list element, 1-based, and a block-mapping value */
  assert_int_equal(vi_scene_edit_assign(e, "forcing.a[2]=0.25", &d), VI_OK);
  assert_int_equal(vi_scene_edit_set_number(e, "stop.xs", 0.05, &d), VI_OK);
  char buf[64];
  assert_int_equal(vi_scene_edit_get(e, "forcing.a[2]", buf, sizeof buf, &d), VI_OK);
  assert_string_equal(buf, "0.25");
  assert_int_equal(vi_scene_edit_get(e, "forcing.a[1]", buf, sizeof buf, &d), VI_OK);
  assert_string_equal(buf, "0.5");
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  assert_int_equal(vi_scene_edit_parse(e, &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_true(vi_model_omega_forcing(m) == 1.25);
  assert_true(vi_model_clearance(m) == 0.05);
  assert_true(vi_model_forcing_cos(m)[0] == 0.5);
  assert_true(vi_model_forcing_cos(m)[1] == 0.25);
  assert_true(vi_model_restitution(m) == 0.7);
  /* comments and line count unchanged */
  assert_non_null(strstr(vi_scene_edit_text(e), "# Ω = 0.9\n"));
  int lines = 0;
  for (const char *c = vi_scene_edit_text(e); *c; c++) lines += *c == '\n';
  assert_int_equal(lines, 10);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  vi_scene_edit_destroy(&e);
}

/* A bad value is reported at the line and column of the key it replaces. */
static void errors_keep_lines(void **state)
{
  (void)state;
  vi_scene_edit *e = edit();
  vi_scene *sc = NULL;
  vi_diag d;
  char msg[1200];
  assert_int_equal(vi_scene_edit_assign(e, "stop.r=1.5", &d), VI_OK);
  assert_int_equal(vi_scene_edit_parse(e, &sc, &d), VI_ERR_RESTITUTION);
  assert_null(sc);
  vi_diag_format(&d, msg, sizeof msg);
  assert_string_equal(d.file, "t.yaml");
  assert_int_equal(d.line, 9);
  assert_int_equal(d.column, 6);
  assert_string_equal(d.key, "stop.r");
  assert_string_equal(d.value, "1.5");
  assert_non_null(strstr(d.message, "command line"));
  vi_scene_edit_destroy(&e);
  /* an unknown key goes in, and the parser names it on its line */
  e = edit();
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omgea=2", &d), VI_OK);
  assert_int_equal(vi_scene_edit_parse(e, &sc, &d), VI_ERR_PARSE);
  assert_int_equal(d.line, 5);
  assert_string_equal(d.key, "forcing.omgea");
  vi_scene_edit_destroy(&e);
}

/* Missing keys are added (flow mapping: same line; block mapping: a new
 * line after its last entry; a whole missing section at the end). */
static void adds_missing_keys(void **state)
{
  (void)state;
  vi_scene_edit *e = edit();
  vi_scene *sc = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_edit_assign(e, "initial.t0=2.5", &d), VI_OK);
  assert_int_equal(vi_scene_edit_assign(e, "run.method=exact", &d), VI_OK);
  assert_int_equal(vi_scene_edit_assign(e, "run.periods=7", &d), VI_OK);
  assert_int_equal(vi_scene_edit_parse(e, &sc, &d), VI_OK);
  assert_true(vi_scene_t0(sc) == 2.5);
  assert_int_equal(vi_scene_method(sc), VI_METHOD_EXACT);
  vi_scene_destroy(&sc);
  /* block mapping */
  assert_int_equal(vi_scene_edit_assign(e, "stop.r=0.5", &d), VI_OK);
  vi_scene_edit_destroy(&e);
  e = edit();
  assert_int_equal(vi_scene_edit_assign(e, "model.rayleigh.beta=0.2", &d), VI_OK);
  assert_non_null(strstr(vi_scene_edit_text(e), "\n  rayleigh: {beta: 0.2}\n"));
  vi_scene_edit_destroy(&e);
}

/* Malformed keys and values, out-of-range indices: refused, named. */
static void bad_edits(void **state)
{
  (void)state;
  vi_scene_edit *e = edit();
  vi_diag d;
  assert_int_equal(vi_scene_edit_assign(e, "forcing.a[3]=1", &d), VI_ERR_PARSE);
  assert_non_null(strstr(d.message, "out of range"));
  assert_int_equal(d.line, 5);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.a[0]=1", &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_edit_assign(e, "forcing..omega=1", &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omega", &d), VI_ERR_PARSE);
  /* injected structure is refused; a flow list is one value */
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omega=1, b: 2", &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omega=x: 2", &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omega=1 # c", &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_edit_assign(e, "name.x=1", &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.a[1].x=1", &d), VI_ERR_PARSE);
  /* failed edits change nothing */
  assert_string_equal(vi_scene_edit_text(e), scene);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.a=[0.6, 0.1]", &d), VI_OK);
  char buf[64];
  assert_int_equal(vi_scene_edit_get(e, "forcing.a[2]", buf, sizeof buf, &d), VI_OK);
  assert_string_equal(buf, "0.1");
  vi_scene_edit_destroy(&e);
}

/* A scene saved with a UTF-8 byte-order mark (editors on Windows): libyaml
 * skips the mark before counting characters, the splice must skip its
 * three bytes too (it cut one byte of the key before). */
static void byte_order_mark(void **state)
{
  (void)state;
  size_t len = strlen(scene);
  char *text = malloc(len + 4);
  assert_non_null(text);
  text[0] = (char)0xEF; /* the mark, U+FEFF in UTF-8 */
  text[1] = (char)0xBB;
  text[2] = (char)0xBF;
  memcpy(text + 3, scene, len + 1);
  vi_scene_edit *e = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_edit_create(text, -1, "bom.yaml", &e, &d), VI_OK);
  assert_int_equal(vi_scene_edit_assign(e, "forcing.omega=1.25", &d), VI_OK);
  const char *t = vi_scene_edit_text(e), *p = strstr(text, "0.9,");
  size_t pre = (size_t)(p - text);
  assert_memory_equal(t, text, pre);
  assert_memory_equal(t + pre, "1.25,", 5);
  assert_string_equal(t + pre + 4, text + pre + 3);
  vi_scene *sc = NULL;
  assert_int_equal(vi_scene_edit_parse(e, &sc, &d), VI_OK);
  vi_scene_destroy(&sc);
  vi_scene_edit_destroy(&e);
  free(text);
}

/* The scene reader's nesting limit applies before the document is loaded:
 * 100 000 levels are refused at the 33rd, as `run` refuses them (loading
 * them first took minutes). */
static void nesting_limit(void **state)
{
  (void)state;
  enum { N = 100000 };
  size_t n = N;
  char *text = malloc(2 * n + 8);
  assert_non_null(text);
  text[0] = 'a';
  text[1] = ':';
  text[2] = ' ';
  memset(text + 3, '[', n);
  memset(text + 3 + n, ']', n);
  text[3 + 2 * n] = '\n';
  text[4 + 2 * n] = '\0';
  vi_scene_edit *e = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_edit_create(text, -1, "deep.yaml", &e, &d), VI_ERR_LIMIT);
  assert_null(e);
  /* the reader's own refusal, word for word */
  assert_string_equal(d.message, "nesting deeper than 32 levels (the limit; a "
                      "scene needs 5)");
  assert_int_equal(d.line, 1);
  assert_int_equal(d.column, 3 + 32); /* level 33: the mapping, then 32 brackets */
  free(text);
}

/* The limit is the caller's (vi_scene_edit_create_limited, `--max-depth`
 * on the --set path): a text 40 levels deep is refused by the default 32
 * and edited under 50; under 4 the text "a: [[[[1]]]]" (5 levels) is
 * refused at its 5th level, and a value that would nest deeper than the
 * limit is refused by vi_scene_edit_set. */
static void nesting_limit_set(void **state)
{
  (void)state;
  char text[128] = "a: ";
  memset(text + 3, '[', 39);
  text[42] = '1';
  memset(text + 43, ']', 39);
  strcpy(text + 82, "\nb: 1\n");
  vi_scene_edit *e = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_edit_create(text, -1, "d.yaml", &e, &d), VI_ERR_LIMIT);
  assert_int_equal(vi_scene_edit_create_limited(text, -1, "d.yaml", 0, &e, &d),
                   VI_ERR_LIMIT);
  assert_int_equal(vi_scene_edit_create_limited(text, -1, "d.yaml", 50, &e, &d), VI_OK);
  assert_int_equal(vi_scene_edit_set(e, "b", "2", &d), VI_OK);
  assert_non_null(strstr(vi_scene_edit_text(e), "b: 2"));
  vi_scene_edit_destroy(&e);
  assert_int_equal(vi_scene_edit_create_limited("a: [[[[1]]]]\nb: 1\n", -1,
                                                "d.yaml", 4, &e, &d), VI_ERR_LIMIT);
  assert_null(e);
  assert_string_equal(d.message, "nesting deeper than 4 levels (the limit; a "
                      "scene needs 5)");
  assert_int_equal(d.line, 1);
  assert_int_equal(d.column, 3 + 4); /* level 5: the mapping, then 4 brackets */
  assert_int_equal(vi_scene_edit_create_limited("a: [[1]]\nb: 1\n", -1,
                                                "d.yaml", 4, &e, &d), VI_OK);
  assert_int_equal(vi_scene_edit_set(e, "b", "[[[[2]]]]", &d), VI_ERR_LIMIT);
  assert_int_equal(vi_scene_edit_set(e, "b", "[[2]]", &d), VI_OK);
  vi_scene_edit_destroy(&e);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(one_value_changes), cmocka_unit_test(errors_keep_lines),
      cmocka_unit_test(adds_missing_keys), cmocka_unit_test(bad_edits),
      cmocka_unit_test(byte_order_mark),
      cmocka_unit_test(nesting_limit), cmocka_unit_test(nesting_limit_set),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
