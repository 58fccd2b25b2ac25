/* scene_fields.c - the tables of the scene format's simple fields
 * (scene_fields.h) and the walks over them that reading and comparing
 * share. The tables follow samples/README.md's Reference, key by key, in
 * the order the writer puts the keys in a file. */
#include "scene_fields.h"

#include <stdio.h>
#include <string.h>

#include "satf/scene.h"

/* A row: its key, type, member of STRUCT, default (def3 for a VEC3),
 * range, and optionally .only_layout or .above_default. */
#define F(type_, key_, member, def_, def3_, range_, ...)                       \
  {                                                                            \
    .key = key_, .type = SCENE_FIELD_##type_,                                  \
    .offset = offsetof(STRUCT, member), .def = def_, .def3 = def3_,            \
    .range = range_, __VA_ARGS__                                               \
  }
#define OTHER(key_)                                                            \
  { .key = key_ }
/* the same, with the range its own code checks */
#define OTHER_IN(key_, range_)                                                 \
  { .key = key_, .range = range_ }
#define N(rows) ((int)(sizeof rows / sizeof rows[0]))

#define R_COORD                                                                \
  { -SATF_SCENE_MAX_COORD, SATF_SCENE_MAX_COORD, 0, 0 }
#define R_NONE                                                                 \
  { 0, 0, 0, 0 }
#define R_UNIT                                                                 \
  { 0, 1, 0, 0 }
#define R_COEF                                                                 \
  { 0, 100, 0, 0 }
#define R_EXPONENT                                                             \
  { 0, 1e4, 1, 0 }
#define R_SHIFT                                                                \
  { -1, 1, 0, 0 }
#define R_TILT                                                                 \
  { -45, 45, 0, 0 }
#define R_IOR                                                                  \
  { 1, 3, 1, 0 }
#define R_ABSORPTION                                                           \
  { 0, 1e3, 0, 0 }
#define R_SIDE                                                                 \
  { 1, SATF_SCENE_MAX_IMAGE, 0, 1 }
#define R_SAMPLES                                                              \
  { 1, SATF_SCENE_MAX_SAMPLES, 0, 1 }
#define R_LAYERS                                                               \
  { 1, SATF_SCENE_MAX_LAYERS, 0, 1 }
#define R_ST                                                                   \
  { 1, SATF_SCENE_MAX_ST, 0, 1 }
#define R_SU                                                                   \
  { SATF_SCENE_MIN_SU, SATF_SCENE_MAX_SU, 0, 1 }
#define R_CORE                                                                 \
  { 0, SATF_SCENE_MAX_CORE, 0, 0 }
#define R_STRANDS                                                              \
  { 1, SATF_SCENE_MAX_STRANDS, 0, 1 }
#define R_SEED                                                                 \
  { 0, 9007199254740991.0, 0, 1 } /* 2^53 - 1: exact in JSON */
#define R_WIDTH                                                                \
  { 0, 0.5, 1, 0 }
/* up to 2: a one-strand cluster is as thin as its strand (satf-import
 * floors its radius at half the strand's thickness), a diameter of 2 */
#define R_TRACK_WIDTH                                                          \
  { 0, 2, 1, 0 }
#define R_SCALE                                                                \
  { 0, 100, 1, 0 }
#define R_FRACTION                                                             \
  { 0, 1, 1, 0 }
#define R_CLUMPS                                                               \
  { 1, SATF_SCENE_MAX_CLUMPS, 0, 1 }
#define R_GRADIENT                                                             \
  { -1, 1, 0, 0 }
#define R_CURL                                                                 \
  { 0, 90, 0, 0 }
#define R_SLICES                                                               \
  { 2, SATF_SCENE_MAX_TRACK_SLICES, 0, 1 }
#define R_FOV                                                                  \
  { 0.1, 179, 0, 0 }
#define R_CLIP                                                                 \
  { 0, SATF_SCENE_MAX_COORD * 10, 1, 0 }
#define R_INTENSITY                                                            \
  { 0, 1e6, 0, 0 }

/* ---- material (SATF eq. 9-12, Scheuermann 2004; the fibre's keys with
 * satf_fiber_material_default's values and the meanings of Cycles'
 * Principled Hair) ---- */

static const float DARK_BROWN[3] = {0.24f, 0.15f, 0.09f};
static const float WHITE[3] = {1.0f, 1.0f, 1.0f};
/* The secondary highlight is light that went through the fibre, so it
 * takes the hair's colour (SATF sec. 6.3); a brighter brown. */
static const float TINTED[3] = {0.55f, 0.38f, 0.24f};

#define STRUCT satf_scene_material
static const scene_field material[] = {
    F(FLOAT, "k_dif", k_dif, 0.7, NULL, R_COEF),
    F(FLOAT, "k_speI", k_speI, 0.3, NULL, R_COEF),
    F(FLOAT, "k_speII", k_speII, 0.4, NULL, R_COEF),
    F(FLOAT, "exponent_I", exponent_I, 80.0, NULL, R_EXPONENT),
    F(FLOAT, "exponent_II", exponent_II, 24.0, NULL, R_EXPONENT),
    OTHER_IN("shift", R_SHIFT),    /* 0.1: the default of both below */
    OTHER_IN("shift_I", R_SHIFT),  /* defaults to shift */
    OTHER_IN("shift_II", R_SHIFT), /* defaults to shift */
    F(VEC3, "f_dif", f_dif, 0, DARK_BROWN, R_UNIT),
    F(VEC3, "f_speI", f_speI, 0, WHITE, R_UNIT),
    F(VEC3, "f_speII", f_speII, 0, TINTED, R_UNIT),
    F(FLOAT, "k_shadow", k_shadow, 0.6, NULL, R_COEF),
    F(FLOAT, "noise", noise, 0.5, NULL, R_UNIT),
    OTHER("model"), /* "kk" or "physical" */
    F(FLOAT, "melanin", melanin, 0.6, NULL, R_UNIT),
    F(FLOAT, "redness", redness, 0.0, NULL, R_UNIT),
    F(FLOAT, "roughness", roughness, 0.3, NULL, R_UNIT),
    F(FLOAT, "radial_roughness", radial_roughness, 0.3, NULL, R_UNIT),
    /* degrees in the scene, as Cycles' Offset */
    F(FLOAT, "cuticle_tilt", cuticle_tilt, 2.0, NULL, R_TILT),
    F(FLOAT, "ior", ior, 1.55, NULL, R_IOR),
    OTHER_IN("absorption", R_ABSORPTION), /* none unless given */
};
#undef STRUCT
const scene_table SCENE_MATERIAL = {"`material`", material, N(material)};

#define STRUCT satf_scene_effects
static const scene_field effects[] = {
    F(BOOL, "satf", satf, 1, NULL, R_NONE),
    F(BOOL, "secondary_highlight", secondary_highlight, 1, NULL, R_NONE),
    F(BOOL, "self_shadow", self_shadow, 1, NULL, R_NONE),
    F(BOOL, "cluster_shadows", cluster_shadows, 1, NULL, R_NONE),
};
#undef STRUCT
const scene_table SCENE_EFFECTS = {"`effects`", effects, N(effects)};

#define STRUCT satf_scene_image
static const scene_field image[] = {
    F(INT, "width", width, 640, NULL, R_SIDE),
    F(INT, "height", height, 480, NULL, R_SIDE),
    F(INT, "samples", samples, 1, NULL, R_SAMPLES, .above_default = 1),
};
#undef STRUCT
const scene_table SCENE_IMAGE = {"`image`", image, N(image)};

/* ---- the hair ---- */

#define STRUCT satf_scene_shell
static const scene_field shell[] = {
    F(INT, "layers", layers, 3, NULL, R_LAYERS),
    F(INT, "st", st, 32, NULL, R_ST),
    F(INT, "su", su, 16, NULL, R_SU),
    F(FLOAT, "core", core, 0.5, NULL, R_CORE),
};
#undef STRUCT
const scene_table SCENE_SHELL = {"`shell` (SATF eq. 3)", shell, N(shell)};

#define STRUCT satf_scene_density
#define ONLY(layout) .only_layout = 1 + SATF_SCENE_LAYOUT_##layout
static const scene_field procedural[] = {
    OTHER("type"),
    F(INT, "strands", strands, 1000, NULL, R_STRANDS),
    OTHER_IN("seed", R_SEED), /* 1; 64 bits */
    OTHER("layout"),          /* a name */
    F(FLOAT, "strand_width", strand_width, 0.03, NULL, R_WIDTH),
    F(FLOAT, "scale", scale, 1.0, NULL, R_SCALE),
    F(INT, "clumps", clumps, 8, NULL, R_CLUMPS, ONLY(CLUMPED)),
    F(FLOAT, "clump_spread", clump_spread, 0.15, NULL, R_FRACTION,
      ONLY(CLUMPED)),
    F(INT, "holes", holes, 4, NULL, R_CLUMPS, ONLY(HOLES)),
    F(FLOAT, "hole_radius", hole_radius, 0.2, NULL, R_FRACTION, ONLY(HOLES)),
    F(FLOAT, "gradient", gradient, 0.8, NULL, R_GRADIENT, ONLY(GRADIENT)),
    F(FLOAT, "curl", curl, 0.0, NULL, R_CURL, .above_default = 1),
};
#undef ONLY
const scene_table SCENE_PROCEDURAL = {"`density`, procedural", procedural,
                                      N(procedural)};

static const scene_field tracks[] = {
    OTHER("type"),
    OTHER_IN("slices", R_SLICES), /* required */
    F(FLOAT, "strand_width", strand_width, 0.03, NULL, R_TRACK_WIDTH),
    F(FLOAT, "scale", scale, 1.0, NULL, R_SCALE),
    F(FLOAT, "curl", curl, 0.0, NULL, R_CURL, .above_default = 1),
    OTHER("tracks"),
    OTHER("ends"),
    OTHER("widths"),
};
#undef STRUCT
const scene_table SCENE_TRACKS = {
    "Density from the cluster's own strands: `\"type\": \"tracks\"`", tracks,
    N(tracks)};

/* ---- camera and lights: the rows their readers, the keyframes and the
 * snapshot's clamps share (the camera's position and target default to a
 * framing of the bounds; the lights are of two kinds) ---- */

static const float Y_UP[3] = {0.0f, 1.0f, 0.0f};

#define STRUCT satf_scene_camera
static const scene_field camera[] = {
    OTHER_IN("position", R_COORD), /* framed from the bounds */
    OTHER_IN("target", R_COORD),   /* the bounds' centre */
    F(VEC3, "up", up, 0, Y_UP, R_COORD),
    F(FLOAT, "fov_y", fov_y, 40.0, NULL, R_FOV),
    /* 0: chosen by the renderer */
    F(FLOAT, "near", near_clip, 0.0, NULL, R_CLIP, .above_default = 1),
    F(FLOAT, "far", far_clip, 0.0, NULL, R_CLIP, .above_default = 1),
    OTHER("keys"),
};
#undef STRUCT
const scene_table SCENE_CAMERA = {"`camera`", camera, N(camera)};

#define STRUCT satf_scene_light
static const scene_field light[] = {
    OTHER("type"),
    OTHER_IN("direction", R_COORD), /* directional: required */
    OTHER_IN("position", R_COORD),  /* point: required */
    F(VEC3, "color", color, 0, WHITE, R_UNIT),
    F(FLOAT, "intensity", intensity, 1.0, NULL, R_INTENSITY),
    OTHER("keys"),
};
#undef STRUCT
const scene_table SCENE_LIGHT = {"`lights[k]`", light, N(light)};

const scene_table *const SCENE_TABLES[] = {
    &SCENE_MATERIAL,   &SCENE_EFFECTS, &SCENE_IMAGE,  &SCENE_SHELL,
    &SCENE_PROCEDURAL, &SCENE_TRACKS,  &SCENE_CAMERA, &SCENE_LIGHT};
const int SCENE_N_TABLES = N(SCENE_TABLES);

/* ---- walks ---- */

const scene_field *scene_field_find(const scene_table *t, const char *key) {
  for (int i = 0; i < t->n; i++)
    if (strcmp(t->fields[i].key, key) == 0)
      return &t->fields[i];
  return NULL;
}

#define MAX_KEYS 32

static satf_status read_row(scene_ctx *ctx, const cJSON *obj,
                            const scene_field *row, void *base) {
  void *at = scene_field_at(row, base);
  switch (row->type) {
  case SCENE_FIELD_FLOAT:
    return scene_key_float(ctx, obj, row->key, &row->range, row->def, at);
  case SCENE_FIELD_INT:
    return scene_key_int(ctx, obj, row->key, &row->range, (int)row->def, at);
  case SCENE_FIELD_BOOL:
    return scene_key_bool(ctx, obj, row->key, (int)row->def, at);
  case SCENE_FIELD_VEC3:
    return scene_key_vec(ctx, obj, row->key, 3, &row->range, row->def3, at);
  case SCENE_FIELD_OTHER: break;
  }
  return SATF_OK;
}

satf_status scene_fields_read(scene_ctx *ctx, const cJSON *obj,
                              const scene_table *t, void *base,
                              scene_field_read_fn other, void *user) {
  const char *keys[MAX_KEYS + 1];
  int n = 0;
  for (int i = 0; i < t->n && n < MAX_KEYS; i++)
    keys[n++] = t->fields[i].key;
  keys[n] = NULL;
  satf_status s = scene_check_keys(ctx, obj, keys);
  for (int i = 0; s == SATF_OK && i < t->n; i++) {
    const scene_field *row = &t->fields[i];
    if (row->type != SCENE_FIELD_OTHER)
      s = read_row(ctx, obj, row, base);
    else if (other)
      s = other(ctx, obj, row, base, user);
  }
  return s;
}

satf_status scene_fields_warn_unused(scene_ctx *ctx, const cJSON *obj,
                                     const scene_table *t, int layout,
                                     const char *const *layout_names) {
  for (int i = 0; i < t->n; i++) {
    const scene_field *row = &t->fields[i];
    if (row->only_layout == 0 || row->only_layout == 1 + layout ||
        !cJSON_GetObjectItemCaseSensitive(obj, row->key))
      continue;
    size_t previous = scene_push_key(ctx, row->key);
    satf_status s = scene_warn(ctx, "ignored: only used by layout \"%s\"",
                               layout_names[row->only_layout - 1]);
    scene_pop(ctx, previous);
    if (s != SATF_OK)
      return s;
  }
  return SATF_OK;
}

static size_t row_bytes(const scene_field *row) {
  switch (row->type) {
  case SCENE_FIELD_FLOAT: return sizeof(float);
  case SCENE_FIELD_INT:
  case SCENE_FIELD_BOOL: return sizeof(int);
  case SCENE_FIELD_VEC3: return 3 * sizeof(float);
  case SCENE_FIELD_OTHER: break;
  }
  return 0;
}

int scene_fields_equal(const scene_table *t, const void *a, const void *b) {
  for (int i = 0; i < t->n; i++) {
    const scene_field *row = &t->fields[i];
    size_t bytes = row_bytes(row);
    if (bytes && memcmp(scene_field_at_const(row, a),
                        scene_field_at_const(row, b), bytes) != 0)
      return 0;
  }
  return 1;
}
