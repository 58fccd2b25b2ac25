/* test_fields.c - the scene format's table of simple fields
 * (online/scene/scene_fields.h) against its reference, samples/README.md:
 * every key of each table is in the README's table of that object and the
 * other way round, with the same type, default and range; a README or a
 * table that lacks a key fails the comparison. And every simple field is
 * parsed, written and compared: a value other than the default survives
 * satf_scene_to_json and satf_scene_parse, and satf_scene_equal sees it. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "satf/fiber.h"
#include "satf/math.h"
#include "satf/scene.h"
#include "scene_fields.h"
#include "test_util.h"

/* ---- the README's tables ---- */

static char *readme_text(void) {
  size_t size;
  char *text = (char *)test_read_file(SATF_SAMPLES_DIR "/README.md", &size);
  assert_non_null(text);
  return text;
}

/* Cell `col` (0-based) of a table line "| a | b | c |", trimmed, into out;
 * 0 when the line has fewer cells. */
static int cell(const char *line, int col, char *out, size_t size) {
  const char *p = strchr(line, '|');
  for (int c = 0; p && c < col; c++)
    p = strchr(p + 1, '|');
  if (!p)
    return 0;
  const char *end = strchr(p + 1, '|');
  const char *nl = strchr(p + 1, '\n');
  if (!end || (nl && nl < end))
    return 0;
  p++;
  while (*p == ' ')
    p++;
  size_t n = (size_t)(end - p);
  while (n > 0 && p[n - 1] == ' ')
    n--;
  snprintf(out, size, "%.*s", (int)n, p);
  return 1;
}

/* The table under the heading `name` in text: its first row's position and
 * the column of `range` (or else `notes`, -1 when neither). NULL when the
 * heading is missing. */
static const char *readme_table(const char *text, const char *name,
                                int *range_col) {
  const char *p = text;
  size_t n = strlen(name);
  for (;;) {
    p = strstr(p, name);
    if (!p)
      return NULL;
    const char *bol = p;
    while (bol > text && bol[-1] != '\n')
      bol--;
    if (*bol == '#' && (p[n] == '\n' || p[n] == '\0') && p[-1] == ' ')
      break;
    p += n;
  }
  const char *header = strstr(p, "\n|");
  assert_non_null(header);
  header++;
  *range_col = -1;
  char c[64];
  for (int col = 0; cell(header, col, c, sizeof c); col++)
    if (strcmp(c, "range") == 0 || (*range_col < 0 && strcmp(c, "notes") == 0))
      *range_col = col;
  const char *rows = strchr(header, '\n'); /* the |---| line */
  return rows ? strchr(rows + 1, '\n') + 1 : NULL;
}

/* The README row of `key` in the table starting at rows, or NULL. */
static const char *readme_row(const char *rows, const char *key) {
  char want[80];
  snprintf(want, sizeof want, "| `%s` |", key);
  for (const char *line = rows; line && *line == '|';) {
    if (strncmp(line, want, strlen(want)) == 0)
      return line;
    line = strchr(line, '\n');
    line = line ? line + 1 : NULL;
  }
  return NULL;
}

/* A README number: "1e4", "10 000 000", "2^53 - 1". */
static double number(const char *s, const char **end) {
  char buf[64];
  size_t n = 0;
  while (*s && (strchr("0123456789.eE+-^ ", *s)) && n + 1 < sizeof buf) {
    if (*s != ' ')
      buf[n++] = *s;
    s++;
  }
  buf[n] = '\0';
  *end = s;
  char *caret = strchr(buf, '^');
  if (caret) { /* B^E - K */
    char *minus = strchr(caret, '-');
    double v = pow(strtod(buf, NULL), strtod(caret + 1, NULL));
    return minus ? v - strtod(minus + 1, NULL) : v;
  }
  return strtod(buf, NULL);
}

/* "[lo, hi]" or "(lo, hi]" at the start of s into r; 0 when s is not one. */
static int interval(const char *s, scene_range *r) {
  if (*s != '[' && *s != '(')
    return 0;
  r->lo_open = *s == '(';
  const char *p;
  r->lo = number(s + 1, &p);
  if (*p != ',')
    return 0;
  r->hi = number(p + 1, &p);
  return *p == ']';
}

/* Where the README says otherwise than the code, each with the reason it
 * is let pass; a new difference fails. */
static const struct {
  const scene_table *table;
  const char *key;
} KNOWN[] = {
    /* the heading names it ("type": "tracks"), no row */
    {&SCENE_TRACKS, "type"},
    /* the README's (0, 0.5] is the procedural density's; a tracks density
     * takes up to 2 (a one-strand cluster as thin as its strand) */
    {&SCENE_TRACKS, "strand_width"},
};

static int known(const scene_table *t, const char *key) {
  for (size_t i = 0; i < sizeof KNOWN / sizeof KNOWN[0]; i++)
    if (KNOWN[i].table == t && strcmp(KNOWN[i].key, key) == 0)
      return 1;
  return 0;
}

/* Compares table t with its README table in text; each difference is
 * appended to why. Returns the number of differences. */
static int compare(const char *text, const scene_table *t, char *why,
                   size_t size) {
  int range_col, bad = 0;
  const char *rows = readme_table(text, t->name, &range_col);
#define DIFF(...)                                                              \
  do {                                                                         \
    size_t used_ = strlen(why);                                                \
    snprintf(why + used_, size - used_, __VA_ARGS__);                          \
    bad++;                                                                     \
  } while (0)
  if (!rows) {
    DIFF("%s: no such table in the README\n", t->name);
    return bad;
  }
  for (int i = 0; i < t->n; i++) {
    const scene_field *f = &t->fields[i];
    const char *row = readme_row(rows, f->key);
    if (!row && known(t, f->key))
      continue;
    if (!row) {
      DIFF("%s.%s: not in the README\n", t->name, f->key);
      continue;
    }
    char type[128], def[256], range[512];
    assert_true(cell(row, 1, type, sizeof type));
    assert_true(cell(row, 2, def, sizeof def));
    range[0] = '\0';
    if (range_col >= 0)
      cell(row, range_col, range, sizeof range);
    const char *want = f->type == SCENE_FIELD_FLOAT  ? "number"
                       : f->type == SCENE_FIELD_INT  ? "integer"
                       : f->type == SCENE_FIELD_BOOL ? "boolean"
                                                     : NULL;
    if (want && strncmp(type, want, strlen(want)) != 0)
      DIFF("%s.%s: README type \"%s\", table %s\n", t->name, f->key, type,
           want);
    if (f->type == SCENE_FIELD_VEC3 && strncmp(type, "rgb", 3) != 0 &&
        strncmp(type, "vec3", 4) != 0)
      DIFF("%s.%s: README type \"%s\", table a 3-vector\n", t->name, f->key,
           type);
    const char *end;
    if ((f->type == SCENE_FIELD_FLOAT || f->type == SCENE_FIELD_INT) &&
        (float)number(def, &end) != (float)f->def)
      DIFF("%s.%s: README default \"%s\", table %g\n", t->name, f->key, def,
           f->def);
    if (f->type == SCENE_FIELD_BOOL &&
        strcmp(def, f->def != 0.0 ? "true" : "false") != 0)
      DIFF("%s.%s: README default \"%s\", table %g\n", t->name, f->key, def,
           f->def);
    if (f->type == SCENE_FIELD_VEC3) {
      const char *p = def;
      int same = *p == '[';
      for (int k = 0; same && k < 3; k++) {
        same =
            (float)number(p + 1, &p) == f->def3[k] && *p == (k < 2 ? ',' : ']');
      }
      if (!same)
        DIFF("%s.%s: README default \"%s\", table [%g, %g, %g]\n", t->name,
             f->key, def, f->def3[0], f->def3[1], f->def3[2]);
    }
    /* a range the table gives (simple numbers always; colours and other
     * keys when the README states one) */
    int has_range = f->range.hi > f->range.lo;
    int numeric = f->type == SCENE_FIELD_FLOAT || f->type == SCENE_FIELD_INT;
    scene_range r;
    if (has_range && (numeric || range[0] == '[' || range[0] == '(') &&
        !known(t, f->key)) {
      if (!interval(range, &r))
        DIFF("%s.%s: README range \"%s\" is not an interval\n", t->name, f->key,
             range);
      else if (r.lo != f->range.lo || r.hi != f->range.hi ||
               r.lo_open != f->range.lo_open)
        DIFF("%s.%s: README range \"%s\", table %c%g, %g]\n", t->name, f->key,
             range, f->range.lo_open ? '(' : '[', f->range.lo, f->range.hi);
    }
  }
  /* and every key of the README's table is in the code's */
  for (const char *line = rows; line && *line == '|';) {
    char key[128];
    if (cell(line, 0, key, sizeof key) && key[0] == '`') {
      key[strlen(key) - 1] = '\0';
      if (!scene_field_find(t, key + 1))
        DIFF("%s.%s: in the README, not in the table\n", t->name, key + 1);
    }
    line = strchr(line, '\n');
    line = line ? line + 1 : NULL;
  }
#undef DIFF
  return bad;
}

static void tables_match_readme(void **state) {
  (void)state;
  char *text = readme_text();
  char why[8192] = "";
  int bad = 0;
  for (int i = 0; i < SCENE_N_TABLES; i++)
    bad += compare(text, SCENE_TABLES[i], why, sizeof why);
  if (bad)
    fail_msg("%d difference(s) between scene_fields.c and "
             "samples/README.md:\n%s",
             bad, why);
  free(text);
}

/* The comparison fails when the README lacks a key the table has. */
static void readme_missing_key_fails(void **state) {
  (void)state;
  char *text = readme_text();
  char *row = strstr(text, "| `clump_spread` |");
  assert_non_null(row);
  char *eol = strchr(row, '\n');
  memmove(row, eol + 1, strlen(eol + 1) + 1);
  char why[4096] = "";
  assert_int_equal(compare(text, &SCENE_PROCEDURAL, why, sizeof why), 1);
  assert_non_null(strstr(why, "clump_spread: not in the README"));
  free(text);
}

/* ... and when the table lacks a key of the README, or says another
 * default or range. */
static void table_missing_key_fails(void **state) {
  (void)state;
  char *text = readme_text();
  scene_field rows[64];
  const scene_table *m = &SCENE_MATERIAL;
  assert_true(m->n <= 64);
  memcpy(rows, m->fields, (size_t)m->n * sizeof *rows);
  scene_table t = {m->name, rows, m->n};
  int noise = -1, ior = -1;
  for (int i = 0; i < t.n; i++) {
    if (strcmp(rows[i].key, "noise") == 0)
      noise = i;
    if (strcmp(rows[i].key, "ior") == 0)
      ior = i;
  }
  assert_true(noise >= 0 && ior >= 0);
  rows[ior].def = 1.5;         /* another default */
  rows[ior].range.hi = 4;      /* another range */
  rows[noise] = rows[t.n - 1]; /* noise forgotten */
  t.n--;
  char why[4096] = "";
  assert_int_equal(compare(text, &t, why, sizeof why), 3);
  assert_non_null(strstr(why, "noise: in the README, not in the table"));
  assert_non_null(strstr(why, "ior: README default"));
  assert_non_null(strstr(why, "ior: README range"));
  free(text);
}

/* The fibre's defaults are satf_fiber_material_default's (the parser took
 * them from it). */
static void fiber_defaults(void **state) {
  (void)state;
  satf_fiber_material def = satf_fiber_material_default();
  const scene_table *m = &SCENE_MATERIAL;
  assert_true((float)scene_field_find(m, "melanin")->def == def.melanin);
  assert_true((float)scene_field_find(m, "redness")->def == def.redness);
  assert_true((float)scene_field_find(m, "roughness")->def == def.roughness);
  assert_true((float)scene_field_find(m, "radial_roughness")->def ==
              def.radial_roughness);
  assert_true((float)scene_field_find(m, "ior")->def == def.ior);
  assert_true((float)scene_field_find(m, "cuticle_tilt")->def ==
              (float)(round(def.cuticle_tilt * 180.0 / SATF_PI * 1e4) / 1e4));
}

/* ---- every simple field read, written and compared ---- */

/* a camera placed, not framed: a framed one moves with fov_y */
static const char SCENE[] =
    "{\"macro_clusters\": [{\"prototype\": {\"trajectory\": [[0, 0, 0], "
    "[0, -1, 0], [0, -2, 0]], \"a\": 0.2}}], \"lights\": [{\"direction\": "
    "[0, 0, -1]}], \"camera\": {\"position\": [0, -1, 10], \"near\": 0.5, "
    "\"far\": 50}}";

/* Where table t's struct lives in scene. */
static void *base_of(satf_scene *scene, const scene_table *t) {
  satf_scene_cluster *c = &scene->macro_clusters[0].prototype;
  if (t == &SCENE_MATERIAL)
    return &scene->material;
  if (t == &SCENE_EFFECTS)
    return &scene->effects;
  if (t == &SCENE_IMAGE)
    return &scene->image;
  if (t == &SCENE_SHELL)
    return &c->shell;
  if (t == &SCENE_PROCEDURAL)
    return &c->density;
  if (t == &SCENE_CAMERA)
    return &scene->camera;
  if (t == &SCENE_LIGHT)
    return &scene->lights[0];
  return NULL; /* SCENE_TRACKS: the procedural rows' members */
}

/* A value of row in its range other than the one at p. */
static void change(const scene_field *row, void *p) {
  double lo = row->range.lo, hi = row->range.hi;
  switch (row->type) {
  case SCENE_FIELD_FLOAT: {
    float *v = p;
    double moved = *v * 1.25 + 0.01;
    *v = (float)(moved <= hi ? moved : 0.5 * (*v + lo));
    break;
  }
  case SCENE_FIELD_INT: {
    int *v = p;
    *v = *v + 1 <= hi ? *v + 1 : *v - 1;
    break;
  }
  case SCENE_FIELD_BOOL: *(int *)p = !*(int *)p; break;
  case SCENE_FIELD_VEC3: {
    float *v = p;
    for (int k = 0; k < 3; k++)
      v[k] = (float)(v[k] > lo ? 0.5 * (v[k] + lo) : 0.5 * (v[k] + hi));
    break;
  }
  case SCENE_FIELD_OTHER: break;
  }
}

static satf_scene *parse(const char *json) {
  satf_scene *s = NULL;
  satf_error err;
  if (satf_scene_parse(json, strlen(json), NULL, &s, &err) != SATF_OK)
    fail_msg("%s\n%s", err.message, json);
  return s;
}

static void every_field_round_trips(void **state) {
  (void)state;
  int checked = 0;
  for (int i = 0; i < SCENE_N_TABLES; i++) {
    const scene_table *t = SCENE_TABLES[i];
    for (int j = 0; j < t->n; j++) {
      const scene_field *row = &t->fields[j];
      if (row->type == SCENE_FIELD_OTHER || t == &SCENE_TRACKS)
        continue;
      if (t == &SCENE_CAMERA && strcmp(row->key, "up") == 0)
        continue; /* normalized: satf_scene_normalize's own test */
      satf_scene *a = parse(SCENE), *b = parse(SCENE);
      void *at = scene_field_at(row, base_of(b, t));
      if (row->only_layout) /* written for its layout only */
        ((satf_scene_density *)base_of(a, t))->layout =
            ((satf_scene_density *)base_of(b, t))->layout =
                (satf_scene_layout)(row->only_layout - 1);
      change(row, at);
      if (satf_scene_equal(a, b))
        fail_msg("%s.%s: a change not seen by satf_scene_equal", t->name,
                 row->key);
      char *json;
      satf_error err;
      assert_int_equal(satf_scene_to_json(b, NULL, &json, &err), SATF_OK);
      satf_scene *c = parse(json);
      if (!satf_scene_equal(b, c) ||
          memcmp(scene_field_at(row, base_of(c, t)), at,
                 row->type == SCENE_FIELD_VEC3 ? 3 * sizeof(float)
                                               : sizeof(float)) != 0)
        fail_msg("%s.%s: not read back as written:\n%s", t->name, row->key,
                 json);
      free(json);
      satf_scene_destroy(a);
      satf_scene_destroy(b);
      satf_scene_destroy(c);
      checked++;
    }
  }
  assert_true(checked >= 40);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(tables_match_readme),
      cmocka_unit_test(readme_missing_key_fails),
      cmocka_unit_test(table_missing_key_fails),
      cmocka_unit_test(fiber_defaults),
      cmocka_unit_test(every_field_round_trips),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
