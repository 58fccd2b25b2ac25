/* scene_cases.h - what the scene tests share: parsing a scene that must
 * load, and a table of malformed scenes each rejected with its own status
 * and message. */
#ifndef SATF_TESTS_SCENE_CASES_H
#define SATF_TESTS_SCENE_CASES_H

#include <stdio.h>
#include <string.h>

#include "satf/scene.h"
#include "test_util.h"

/* Parses json as file `name`; fails the test (printing why) unless it
 * loads. Warnings are printed. */
static inline satf_scene *parse_ok(const char *json, const char *name) {
  satf_scene *scene = NULL;
  satf_error err;
  satf_error_clear(&err);
  satf_status s = satf_scene_parse(json, strlen(json), name, &scene, &err);
  if (s != SATF_OK)
    fprintf(stderr, "unexpected failure: %s\n", err.message);
  assert_int_equal(s, SATF_OK);
  assert_non_null(scene);
  for (int i = 0; i < satf_scene_warning_count(scene); i++)
    fprintf(stderr, "warning: %s\n", satf_scene_warning(scene, i));
  return scene;
}

typedef struct bad_case {
  const char *json;
  satf_status status;
  const char *expect; /* substring of the message */
} bad_case;

enum { BAD_CASES_MAX = 256 };

/* Every case fails with its status, a message that starts with the file
 * name and contains its text, no scene, and a message no other case has. */
static inline void check_bad_cases(const bad_case *cases, size_t n,
                                   const char *name) {
  static char messages[BAD_CASES_MAX][sizeof(((satf_error *)0)->message)];
  assert_true(n <= BAD_CASES_MAX);
  size_t name_len = strlen(name);
  for (size_t i = 0; i < n; i++) {
    satf_scene *scene = (satf_scene *)&messages; /* must be reset to NULL */
    satf_error err;
    satf_error_clear(&err);
    satf_status s = satf_scene_parse(cases[i].json, strlen(cases[i].json), name,
                                     &scene, &err);
    if (s == SATF_OK || !strstr(err.message, cases[i].expect) ||
        s != cases[i].status) {
      fprintf(stderr,
              "case %zu: %s\n  status %d, message: %s\n  expected: %s\n", i,
              cases[i].json, (int)s, err.message, cases[i].expect);
      fail();
    }
    assert_null(scene);
    assert_int_equal(err.status, s);
    assert_memory_equal(err.message, name, name_len);
    strcpy(messages[i], err.message);
    for (size_t j = 0; j < i; j++)
      assert_string_not_equal(messages[i], messages[j]);
  }
}

#endif
