/* scene_equal.c - comparisons of scenes: the cheap ones a renderer uses to
 * see what moved between two snapshots, and satf_scene_equal, which
 * compares everything a scene file can say, keyframes included. */
#include <string.h>

#include "scene_anim.h"
#include "scene_fields.h"

static int floats_equal(const float *a, const float *b, int n) {
  return n == 0 || memcmp(a, b, (size_t)n * sizeof *a) == 0;
}

static int curves_equal(const satf_scene_curve *a, const satf_scene_curve *b) {
  return a->count == b->count && floats_equal(a->values, b->values, a->count);
}

static int strings_equal(const char *a, const char *b) {
  return (!a && !b) || (a && b && strcmp(a, b) == 0);
}

static int tracks_equal(const satf_scene_density *a,
                        const satf_scene_density *b) {
  if (a->track_slices != b->track_slices || a->n_tracks != b->n_tracks)
    return 0;
  size_t points = 0;
  for (int k = 0; k < a->n_tracks; k++) {
    if (a->track_first[k] != b->track_first[k] ||
        a->track_count[k] != b->track_count[k])
      return 0;
    points += (size_t)a->track_count[k];
  }
  if (!a->track_ends != !b->track_ends ||
      (a->track_ends &&
       !floats_equal(a->track_ends, b->track_ends, 6 * a->n_tracks)))
    return 0;
  if (!a->track_width != !b->track_width ||
      (a->track_width &&
       !floats_equal(a->track_width, b->track_width, a->n_tracks)))
    return 0;
  return points == 0 ||
         floats_equal(a->track_xy, b->track_xy, (int)(2 * points));
}

static int densities_equal(const satf_scene_density *a,
                           const satf_scene_density *b) {
  /* the procedural table's numbers are the tracks' too (strand_width,
   * scale), with the parameters of every layout */
  return a->type == b->type && a->seed == b->seed && a->layout == b->layout &&
         scene_fields_equal(&SCENE_PROCEDURAL, a, b) &&
         strings_equal(a->vdb_file, b->vdb_file) &&
         strings_equal(a->vdb_grid, b->vdb_grid) && tracks_equal(a, b);
}

int satf_scene_prototype_equal(const satf_scene_cluster *a,
                               const satf_scene_cluster *b) {
  return a->n_points == b->n_points &&
         floats_equal(a->trajectory, b->trajectory, 3 * a->n_points) &&
         curves_equal(&a->a, &b->a) && curves_equal(&a->b, &b->b) &&
         curves_equal(&a->twist, &b->twist) &&
         scene_fields_equal(&SCENE_SHELL, &a->shell, &b->shell) &&
         densities_equal(&a->density, &b->density);
}

int satf_scene_instances_equal(const satf_scene_macro_cluster *a,
                               const satf_scene_macro_cluster *b) {
  if (a->n_instances != b->n_instances)
    return 0;
  for (int j = 0; j < a->n_instances; j++)
    if (!floats_equal(a->instances[j].m, b->instances[j].m, 16))
      return 0;
  return 1;
}

int satf_scene_camera_equal(const satf_scene_camera *a,
                            const satf_scene_camera *b) {
  return floats_equal(a->position, b->position, 3) &&
         floats_equal(a->target, b->target, 3) &&
         scene_fields_equal(&SCENE_CAMERA, a, b) &&
         a->automatic == b->automatic;
}

int satf_scene_light_equal(const satf_scene_light *a,
                           const satf_scene_light *b) {
  return a->type == b->type && floats_equal(a->direction, b->direction, 3) &&
         floats_equal(a->position, b->position, 3) &&
         scene_fields_equal(&SCENE_LIGHT, a, b);
}

/* ---- keyframes ---- */

static int doubles_equal(const double *a, const double *b, int n) {
  return n == 0 || memcmp(a, b, (size_t)n * sizeof *a) == 0;
}

/* Both NULL (the key keeps the static value) or both n equal floats. */
static int key_arrays_equal(const float *a, const float *b, int n) {
  return (!a && !b) || (a && b && floats_equal(a, b, n));
}

static int xforms_equal(const scene_xform *a, const scene_xform *b) {
  return a->is_matrix == b->is_matrix && floats_equal(a->m, b->m, 16) &&
         floats_equal(a->translate, b->translate, 3) &&
         floats_equal(a->axis, b->axis, 3) &&
         doubles_equal(&a->degrees, &b->degrees, 1) &&
         floats_equal(a->scale, b->scale, 3);
}

static const scene_track no_keys = {0, NULL, NULL};

static const scene_track *track_at(const scene_track *tracks, int n, int i) {
  return i < n ? &tracks[i] : &no_keys;
}

/* Equal frames; the keys are compared by the caller. */
static int frames_equal(const scene_track *a, const scene_track *b) {
  return a->n_keys == b->n_keys &&
         doubles_equal(a->frames, b->frames, a->n_keys);
}

static int proto_tracks_equal(const scene_track *a, const scene_track *b,
                              const satf_scene_cluster *c) {
  if (!frames_equal(a, b))
    return 0;
  const scene_proto_key *ka = a->keys, *kb = b->keys;
  for (int k = 0; k < a->n_keys; k++)
    if (!key_arrays_equal(ka[k].trajectory, kb[k].trajectory,
                          3 * c->n_points) ||
        !key_arrays_equal(ka[k].a, kb[k].a, c->a.count) ||
        !key_arrays_equal(ka[k].b, kb[k].b, c->b.count) ||
        !key_arrays_equal(ka[k].twist, kb[k].twist, c->twist.count))
      return 0;
  return 1;
}

static int instance_tracks_equal(const scene_instance_track *a,
                                 const scene_instance_track *b) {
  if (a->macro_cluster != b->macro_cluster || a->instance != b->instance ||
      !xforms_equal(&a->base, &b->base) || !frames_equal(&a->track, &b->track))
    return 0;
  const scene_xform_key *ka = a->track.keys, *kb = b->track.keys;
  for (int k = 0; k < a->track.n_keys; k++)
    if (!xforms_equal(&ka[k].form, &kb[k].form) ||
        !floats_equal(ka[k].translate, kb[k].translate, 3) ||
        !floats_equal(ka[k].stretch, kb[k].stretch, 9) ||
        !doubles_equal(ka[k].rotation, kb[k].rotation, 4))
      return 0;
  return 1;
}

static int camera_tracks_equal(const scene_track *a, const scene_track *b) {
  if (!frames_equal(a, b))
    return 0;
  const scene_camera_key *ka = a->keys, *kb = b->keys;
  for (int k = 0; k < a->n_keys; k++)
    if (!floats_equal(ka[k].position, kb[k].position, 3) ||
        !floats_equal(ka[k].target, kb[k].target, 3) ||
        !floats_equal(ka[k].up, kb[k].up, 3) ||
        !floats_equal(&ka[k].fov_y, &kb[k].fov_y, 1) ||
        ka[k].given != kb[k].given)
      return 0;
  return 1;
}

static int light_tracks_equal(const scene_track *a, const scene_track *b) {
  if (!frames_equal(a, b))
    return 0;
  const scene_light_key *ka = a->keys, *kb = b->keys;
  for (int k = 0; k < a->n_keys; k++)
    if (!floats_equal(ka[k].vector, kb[k].vector, 3) ||
        !floats_equal(ka[k].color, kb[k].color, 3) ||
        !floats_equal(&ka[k].intensity, &kb[k].intensity, 1) ||
        ka[k].given != kb[k].given)
      return 0;
  return 1;
}

static int animations_equal(const satf_scene *sa, const satf_scene *sb) {
  const satf_scene_animation *a = sa->animation, *b = sb->animation;
  if (!a || !b)
    return !a && !b;
  if (!doubles_equal(&a->fps, &b->fps, 1) || a->first != b->first ||
      a->last != b->last || a->total_keys != b->total_keys ||
      a->n_instance_tracks != b->n_instance_tracks ||
      a->camera_sets_position != b->camera_sets_position ||
      !camera_tracks_equal(&a->camera, &b->camera))
    return 0;
  for (int i = 0; i < sa->n_macro_clusters; i++)
    if (!proto_tracks_equal(track_at(a->protos, a->n_protos, i),
                            track_at(b->protos, b->n_protos, i),
                            &sa->macro_clusters[i].prototype))
      return 0;
  for (int i = 0; i < a->n_instance_tracks; i++)
    if (!instance_tracks_equal(&a->instances[i], &b->instances[i]))
      return 0;
  for (int i = 0; i < sa->n_lights; i++)
    if (!light_tracks_equal(track_at(a->lights, a->n_lights, i),
                            track_at(b->lights, b->n_lights, i)))
      return 0;
  return 1;
}

/* ---- everything ---- */

static int materials_equal(const satf_scene_material *a,
                           const satf_scene_material *b) {
  return scene_fields_equal(&SCENE_MATERIAL, a, b) && a->model == b->model &&
         floats_equal(&a->shift_I, &b->shift_I, 1) &&
         floats_equal(&a->shift_II, &b->shift_II, 1) &&
         a->has_absorption == b->has_absorption &&
         (!a->has_absorption || floats_equal(a->absorption, b->absorption, 3));
}

static int meshes_equal(const satf_scene *a, const satf_scene *b) {
  if (a->n_meshes != b->n_meshes)
    return 0;
  for (int i = 0; i < a->n_meshes; i++)
    if (!strings_equal(a->meshes[i].file, b->meshes[i].file) ||
        !floats_equal(a->meshes[i].color, b->meshes[i].color, 3) ||
        !floats_equal(a->meshes[i].m, b->meshes[i].m, 16))
      return 0;
  return 1;
}

int satf_scene_equal(const satf_scene *a, const satf_scene *b) {
  if (!a || !b)
    return a == b;
  if (!strings_equal(a->description, b->description) ||
      !strings_equal(a->database, b->database) ||
      !strings_equal(a->strands_file, b->strands_file) ||
      a->n_macro_clusters != b->n_macro_clusters ||
      a->n_lights != b->n_lights ||
      !materials_equal(&a->material, &b->material) ||
      !scene_fields_equal(&SCENE_EFFECTS, &a->effects, &b->effects) ||
      !satf_scene_camera_equal(&a->camera, &b->camera) ||
      !floats_equal(a->background, b->background, 3) ||
      !scene_fields_equal(&SCENE_IMAGE, &a->image, &b->image) ||
      !meshes_equal(a, b))
    return 0;
  for (int i = 0; i < a->n_macro_clusters; i++) {
    const satf_scene_macro_cluster *ma = &a->macro_clusters[i];
    const satf_scene_macro_cluster *mb = &b->macro_clusters[i];
    if (!strings_equal(ma->name, mb->name) ||
        !satf_scene_prototype_equal(&ma->prototype, &mb->prototype) ||
        !satf_scene_instances_equal(ma, mb))
      return 0;
  }
  for (int i = 0; i < a->n_lights; i++)
    if (!satf_scene_light_equal(&a->lights[i], &b->lights[i]))
      return 0;
  return animations_equal(a, b);
}
