/* test_cli.c - the shared argument loop and the strict number parsers,
 * including the exact wording of their messages, which the tools' users
 * and command-line tests see. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "capture.h"
#include "satf/common.h"

#define ARGC(a) ((int)(sizeof(a) / sizeof(a[0])))

static void loop_visits_flags_values_and_positionals(void **state) {
  (void)state;
  char *argv[] = {"prog", "-o",         "out.exr", "--samples", "12",
                  "-q",   "scene.json", "",        "-"};
  satf_cli_args it;
  satf_cli_begin(&it, "prog", ARGC(argv), argv);
  const char *out = NULL;
  long samples = 0;
  int quiet = 0, positionals = 0, unknown = 0;
  const char *first_positional = NULL;
  while (satf_cli_next(&it)) {
    if (satf_cli_is(&it, "-o", "--output")) {
      assert_int_equal(satf_cli_value(&it, &out), 0);
    } else if (satf_cli_is(&it, NULL, "--samples")) {
      assert_int_equal(satf_cli_value_int(&it, 1, 100, &samples), 0);
    } else if (satf_cli_is(&it, "-q", "--quiet")) {
      quiet = 1;
    } else if (satf_cli_positional(&it)) {
      if (!positionals++)
        first_positional = it.arg;
    } else {
      unknown++;
      assert_string_equal(it.arg, "-"); /* a lone "-" is an option */
    }
  }
  assert_string_equal(out, "out.exr");
  assert_int_equal(samples, 12);
  assert_int_equal(quiet, 1);
  assert_int_equal(positionals, 2); /* "scene.json" and "" */
  assert_string_equal(first_positional, "scene.json");
  assert_int_equal(unknown, 1);
  assert_null(it.arg);
  assert_int_equal(satf_cli_next(&it), 0); /* stays at the end */
}

static void short_and_long_names_match_exactly(void **state) {
  (void)state;
  char *argv[] = {"prog", "--output", "--out", "-o"};
  satf_cli_args it;
  satf_cli_begin(&it, "prog", ARGC(argv), argv);
  assert_true(satf_cli_next(&it));
  assert_true(satf_cli_is(&it, "-o", "--output"));
  assert_false(satf_cli_is(&it, "-o", NULL));
  assert_true(satf_cli_next(&it));
  assert_false(satf_cli_is(&it, "-o", "--output")); /* no prefixes */
  assert_true(satf_cli_next(&it));
  assert_true(satf_cli_is(&it, "-o", NULL));
  assert_false(satf_cli_is(&it, NULL, NULL));
}

static void value_is_taken_verbatim(void **state) {
  (void)state;
  char *argv[] = {"prog", "--db", "--help", "--size", "-5"};
  satf_cli_args it;
  satf_cli_begin(&it, "prog", ARGC(argv), argv);
  const char *db = NULL, *size = NULL;
  assert_true(satf_cli_next(&it));
  assert_int_equal(satf_cli_value(&it, &db), 0);
  assert_string_equal(db, "--help");
  assert_true(satf_cli_next(&it));
  assert_string_equal(it.arg, "--size");
  assert_int_equal(satf_cli_value(&it, &size), 0);
  assert_string_equal(size, "-5");
  assert_false(satf_cli_next(&it));
}

static void missing_value_is_reported_with_the_flag(void **state) {
  (void)state;
  char *argv[] = {"satf-render", "scene.json", "--db"};
  satf_cli_args it;
  satf_cli_begin(&it, "satf-render", ARGC(argv), argv);
  assert_true(satf_cli_next(&it));
  assert_true(satf_cli_next(&it));
  const char *value = "unchanged";
  capture c;
  capture_begin(&c);
  int rc = satf_cli_value(&it, &value);
  const char *msg = capture_end(&c);
  assert_int_equal(rc, -1);
  assert_string_equal(value, "unchanged");
  assert_string_equal(msg, "satf-render: --db needs a value (see --help)\n");
  /* the number helpers report the same before parsing anything */
  long n = 7;
  capture_begin(&c);
  rc = satf_cli_value_int(&it, 0, 10, &n);
  msg = capture_end(&c);
  assert_int_equal(rc, -1);
  assert_int_equal(n, 7);
  assert_string_equal(msg, "satf-render: --db needs a value (see --help)\n");
}

static void unknown_option_message_and_status(void **state) {
  (void)state;
  char *argv[] = {"satf-render", "--frobnicate"};
  satf_cli_args it;
  satf_cli_begin(&it, "satf-render", ARGC(argv), argv);
  assert_true(satf_cli_next(&it));
  assert_false(satf_cli_positional(&it));
  capture c;
  capture_begin(&c);
  int rc = satf_cli_unknown(&it);
  const char *msg = capture_end(&c);
  assert_int_equal(rc, 2);
  assert_string_equal(msg, "satf-render: unknown option '--frobnicate' (see "
                           "--help)\n");
}

/* A slip of at most two edits gets the nearest option the loop asked
 * about; anything further gets no guess. */
static void misspelt_option_gets_did_you_mean(void **state) {
  (void)state;
  assert_int_equal(satf_cli_edit_distance("--frame", "--frames"), 1);
  assert_int_equal(satf_cli_edit_distance("--compsite", "--composite"), 1);
  assert_int_equal(satf_cli_edit_distance("--sizes", "--seed"), 3);
  assert_int_equal(satf_cli_edit_distance("", "--db"), 4);
  const char *cases[][2] = {{"--frame", "satf-render: unknown option "
                                        "'--frame' (did you mean "
                                        "'--frames'?) (see --help)\n"},
                            {"--bogus", "satf-render: unknown option "
                                        "'--bogus' (see --help)\n"}};
  for (int k = 0; k < 2; k++) {
    char *argv[] = {"satf-render", (char *)cases[k][0]};
    satf_cli_args it;
    satf_cli_begin(&it, "satf-render", ARGC(argv), argv);
    assert_true(satf_cli_next(&it));
    assert_false(satf_cli_is(&it, "-o", "--output"));
    assert_false(satf_cli_is(&it, NULL, "--frames"));
    assert_false(satf_cli_is(&it, NULL, "--db"));
    capture c;
    capture_begin(&c);
    assert_int_equal(satf_cli_unknown(&it), 2);
    assert_string_equal(capture_end(&c), cases[k][1]);
  }
}

static void hint_and_start_can_be_changed(void **state) {
  (void)state;
  /* satf-db lookup: options start after "lookup FILE", no "(see --help)" */
  char *argv[] = {"satf-db", "lookup", "db.exr", "--k"};
  satf_cli_args it;
  satf_cli_begin(&it, "satf-db", ARGC(argv), argv);
  it.next = 3;
  it.hint = "";
  assert_true(satf_cli_next(&it));
  assert_string_equal(it.arg, "--k");
  const char *v;
  capture c;
  capture_begin(&c);
  assert_int_equal(satf_cli_value(&it, &v), -1);
  assert_string_equal(capture_end(&c), "satf-db: --k needs a value\n");
  capture_begin(&c);
  assert_int_equal(satf_cli_unknown(&it), 2);
  assert_string_equal(capture_end(&c), "satf-db: unknown option '--k'\n");
}

static void double_dash_is_an_option_unless_enabled(void **state) {
  (void)state;
  char *argv[] = {"prog", "a", "--", "-o", "--", "b"};
  satf_cli_args it;
  satf_cli_begin(&it, "prog", ARGC(argv), argv);
  assert_true(satf_cli_next(&it));
  assert_true(satf_cli_next(&it));
  assert_string_equal(it.arg, "--"); /* off: an (unknown) option */
  assert_false(satf_cli_positional(&it));

  satf_cli_begin(&it, "prog", ARGC(argv), argv);
  it.dashdash = 1;
  const char *seen[8];
  int n = 0;
  while (satf_cli_next(&it)) {
    assert_true(satf_cli_positional(&it));
    assert_false(satf_cli_is(&it, "-o", NULL)); /* "-o" after "--" */
    seen[n++] = it.arg;
  }
  /* the first "--" is skipped; the second is an ordinary positional */
  assert_int_equal(n, 4);
  assert_string_equal(seen[0], "a");
  assert_string_equal(seen[1], "-o");
  assert_string_equal(seen[2], "--");
  assert_string_equal(seen[3], "b");
}

static void value_helpers_parse_with_the_spelled_flag(void **state) {
  (void)state;
  char *argv[] = {"prog", "-n", "42",    "--seed", "0x10", "--k",
                  "2.5",  "-s", "64x48", "-n",     "99"};
  satf_cli_args it;
  satf_cli_begin(&it, "prog", ARGC(argv), argv);
  long n = 0, w = 0, h = 0;
  uint64_t seed = 0;
  double k = 0;
  assert_true(satf_cli_next(&it));
  assert_int_equal(satf_cli_value_int(&it, 0, 50, &n), 0);
  assert_int_equal(n, 42);
  assert_true(satf_cli_next(&it));
  assert_int_equal(satf_cli_value_u64(&it, &seed), 0);
  assert_int_equal(seed, 16);
  assert_true(satf_cli_next(&it));
  assert_int_equal(satf_cli_value_double(&it, 0, 10, &k), 0);
  assert_true(k == 2.5);
  assert_true(satf_cli_next(&it));
  assert_int_equal(satf_cli_value_size(&it, 16, 8192, &w, &h), 0);
  assert_int_equal(w, 64);
  assert_int_equal(h, 48);
  assert_true(satf_cli_next(&it));
  capture c;
  capture_begin(&c);
  assert_int_equal(satf_cli_value_int(&it, 0, 50, &n), -1);
  assert_string_equal(capture_end(&c),
                      "prog: -n: 99 is out of range [0, 50]\n");
  assert_int_equal(n, 42);
  assert_false(satf_cli_next(&it));
}

/* Runs a parser on text and returns what it printed ("" on success). */
static const char *int_msg(const char *text, long lo, long hi, long *out,
                           int *rc) {
  static capture c;
  capture_begin(&c);
  *rc = satf_cli_int("p", "--n", text, lo, hi, out);
  return capture_end(&c);
}

static void int_parser_is_strict(void **state) {
  (void)state;
  long v = -99;
  int rc;
  assert_string_equal(int_msg("17", 0, 20, &v, &rc), "");
  assert_int_equal(rc, 0);
  assert_int_equal(v, 17);
  assert_string_equal(int_msg("-3", -3, 20, &v, &rc), ""); /* lo inclusive */
  assert_int_equal(v, -3);
  assert_string_equal(int_msg("20", -3, 20, &v, &rc), ""); /* hi inclusive */
  assert_int_equal(v, 20);
  v = 5;
  const char *bad[] = {"abc", "12x", "", "1.5", "0x10", "1e3"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    char expect[96];
    snprintf(expect, sizeof expect, "p: --n: expected an integer, got '%s'\n",
             bad[i]);
    assert_string_equal(int_msg(bad[i], 0, 1000, &v, &rc), expect);
    assert_int_equal(rc, -1);
    assert_int_equal(v, 5); /* untouched on failure */
  }
  assert_string_equal(int_msg(NULL, 0, 10, &v, &rc),
                      "p: --n: expected an integer, got ''\n");
  assert_string_equal(int_msg("99999999999999999999999", 0, 10, &v, &rc),
                      "p: --n: expected an integer, got "
                      "'99999999999999999999999'\n");
  assert_string_equal(int_msg("21", 0, 20, &v, &rc),
                      "p: --n: 21 is out of range [0, 20]\n");
  assert_string_equal(int_msg("-1", 0, 20, &v, &rc),
                      "p: --n: -1 is out of range [0, 20]\n");
  assert_int_equal(rc, -1);
  assert_int_equal(v, 5);
}

static const char *u64_msg(const char *text, uint64_t *out, int *rc) {
  static capture c;
  capture_begin(&c);
  *rc = satf_cli_u64("p", "--seed", text, out);
  return capture_end(&c);
}

static void u64_parser_takes_all_64_bits_and_no_sign(void **state) {
  (void)state;
  uint64_t v = 0;
  int rc;
  assert_string_equal(u64_msg("18446744073709551615", &v, &rc), "");
  assert_int_equal(rc, 0);
  assert_true(v == UINT64_MAX);
  assert_string_equal(u64_msg("0x1F", &v, &rc), ""); /* C bases */
  assert_true(v == 31);
  assert_string_equal(u64_msg("010", &v, &rc), "");
  assert_true(v == 8);
  v = 77;
  const char *bad[] = {"-4", " -4", "", "18446744073709551616", "12x", "seed"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    char expect[128];
    snprintf(expect, sizeof expect,
             "p: --seed: expected a non-negative integer, got '%s'\n", bad[i]);
    assert_string_equal(u64_msg(bad[i], &v, &rc), expect);
    assert_int_equal(rc, -1);
    assert_true(v == 77);
  }
}

static const char *double_msg(const char *text, double lo, double hi,
                              double *out, int *rc) {
  static capture c;
  capture_begin(&c);
  *rc = satf_cli_double("p", "--k", text, lo, hi, out);
  return capture_end(&c);
}

static void double_parser_rejects_non_finite(void **state) {
  (void)state;
  double v = 0;
  int rc;
  assert_string_equal(double_msg("1e-3", 0, 1, &v, &rc), "");
  assert_int_equal(rc, 0);
  assert_true(v == 1e-3);
  assert_string_equal(double_msg("-2.5", -2.5, 1, &v, &rc), "");
  assert_true(v == -2.5);
  v = 9;
  const char *bad[] = {"nan",   "NaN", "inf",  "-inf", "infinity",
                       "1e400", "",    "1.5x", "x",    "1,5"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    char expect[96];
    snprintf(expect, sizeof expect,
             "p: --k: expected a finite number, got '%s'\n", bad[i]);
    assert_string_equal(double_msg(bad[i], -1e9, 1e9, &v, &rc), expect);
    assert_int_equal(rc, -1);
    assert_true(v == 9);
  }
  assert_string_equal(double_msg("1000001", 0, 1e6, &v, &rc),
                      "p: --k: 1e+06 is out of range [0, 1e+06]\n");
  assert_string_equal(double_msg("-0.5", 0, 1, &v, &rc),
                      "p: --k: -0.5 is out of range [0, 1]\n");
  assert_int_equal(rc, -1);
  assert_true(v == 9);
}

static const char *size_msg(const char *text, long *w, long *h, int *rc) {
  static capture c;
  capture_begin(&c);
  *rc = satf_cli_size("p", "--size", text, 16, 8192, w, h);
  return capture_end(&c);
}

static void size_parser_needs_both_sides(void **state) {
  (void)state;
  long w = 0, h = 0;
  int rc;
  assert_string_equal(size_msg("640x480", &w, &h, &rc), "");
  assert_int_equal(rc, 0);
  assert_int_equal(w, 640);
  assert_int_equal(h, 480);
  const char *shape[] = {"640", "x480", "",
                         "123456789012345678901234567890"
                         "12x16"};
  for (size_t i = 0; i < sizeof shape / sizeof shape[0]; i++) {
    char expect[128];
    snprintf(expect, sizeof expect,
             "p: --size: expected WIDTHxHEIGHT, got '%s'\n", shape[i]);
    assert_string_equal(size_msg(shape[i], &w, &h, &rc), expect);
    assert_int_equal(rc, -1);
  }
  assert_string_equal(size_msg("640x", &w, &h, &rc),
                      "p: --size: expected an integer, got ''\n");
  assert_string_equal(size_msg("64xabc", &w, &h, &rc),
                      "p: --size: expected an integer, got 'abc'\n");
  assert_string_equal(size_msg("64x48x2", &w, &h, &rc),
                      "p: --size: expected an integer, got '48x2'\n");
  assert_string_equal(size_msg("0x480", &w, &h, &rc),
                      "p: --size: 0 is out of range [16, 8192]\n");
  assert_string_equal(size_msg("640x9000", &w, &h, &rc),
                      "p: --size: 9000 is out of range [16, 8192]\n");
  assert_int_equal(rc, -1);
  /* the width is stored before the height is parsed; the caller exits */
  assert_int_equal(w, 640);
  assert_int_equal(h, 480);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(loop_visits_flags_values_and_positionals),
      cmocka_unit_test(short_and_long_names_match_exactly),
      cmocka_unit_test(value_is_taken_verbatim),
      cmocka_unit_test(missing_value_is_reported_with_the_flag),
      cmocka_unit_test(unknown_option_message_and_status),
      cmocka_unit_test(misspelt_option_gets_did_you_mean),
      cmocka_unit_test(hint_and_start_can_be_changed),
      cmocka_unit_test(double_dash_is_an_option_unless_enabled),
      cmocka_unit_test(value_helpers_parse_with_the_spelled_flag),
      cmocka_unit_test(int_parser_is_strict),
      cmocka_unit_test(u64_parser_takes_all_64_bits_and_no_sign),
      cmocka_unit_test(double_parser_rejects_non_finite),
      cmocka_unit_test(size_parser_needs_both_sides),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
