/* import_scene.c - writes fitted clusters as a scene file (the format of
 * samples/README.md, read by satf_scene_load): one macro-cluster per
 * prototype with an instance per member cluster, each prototype's density
 * procedural (its real strand count, the estimated strand width and
 * layout) or the hairstyle's OpenVDB grid, a camera framing the hair, a
 * key and a fill light. */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/import.h"

/* A number rounded to 7 significant digits, so the file stays readable and
 * floats do not print as 17-digit doubles. */
static cJSON *num(double v) {
  char buf[32];
  snprintf(buf, sizeof buf, "%.7g", v);
  return cJSON_CreateNumber(strtod(buf, NULL));
}

static cJSON *num_array(const float *v, int n) {
  cJSON *a = cJSON_CreateArray();
  for (int i = 0; a && i < n; i++)
    cJSON_AddItemToArray(a, num(v[i]));
  return a;
}

static cJSON *vec3(double x, double y, double z) {
  cJSON *a = cJSON_CreateArray();
  if (a) {
    cJSON_AddItemToArray(a, num(x));
    cJSON_AddItemToArray(a, num(y));
    cJSON_AddItemToArray(a, num(z));
  }
  return a;
}

satf_scene_shell satf_import_choose_shell(const satf_import_fit *fit) {
  satf_scene_shell sh;
  /* more layers resolve the density of more strands */
  int layers =
      3 + (int)floor(log10(fit->strands > 10 ? fit->strands / 10.0 : 1.0));
  sh.layers = layers < 3 ? 3 : layers > 6 ? 6 : layers;
  /* HSVs about as long along t as the cluster is wide */
  float r = fit->radius > 0.0f ? fit->radius : 1.0f;
  int st = (int)lroundf(fit->length / r);
  sh.st = st < 8 ? 8 : st > 64 ? 64 : st;
  double ma = 0.0, mb = 0.0;
  for (int j = 0; j < fit->n_radius; j++) {
    ma += fit->a[j];
    mb += fit->b[j];
  }
  double aspect = ma > mb ? ma / mb : mb / ma;
  sh.su = aspect <= 1.5 ? 16 : aspect <= 3.0 ? 24 : 32;
  sh.core = 0.4f;
  return sh;
}

static cJSON *cluster_json(const satf_import_fit *f,
                           const satf_import_scene_options *o, uint64_t seed) {
  cJSON *c = cJSON_CreateObject();
  cJSON *traj = cJSON_CreateArray();
  for (int i = 0; i < f->n_ctrl; i++)
    cJSON_AddItemToArray(
        traj, vec3(f->traj[3 * i], f->traj[3 * i + 1], f->traj[3 * i + 2]));
  cJSON_AddItemToObject(c, "trajectory", traj);
  cJSON_AddItemToObject(c, "a", num_array(f->a, f->n_radius));
  cJSON_AddItemToObject(c, "b", num_array(f->b, f->n_radius));
  cJSON_AddItemToObject(c, "twist", num_array(f->twist, f->n_radius));
  satf_scene_shell sh = satf_import_choose_shell(f);
  cJSON *shell = cJSON_CreateObject();
  cJSON_AddNumberToObject(shell, "layers", sh.layers);
  cJSON_AddNumberToObject(shell, "st", sh.st);
  cJSON_AddNumberToObject(shell, "su", sh.su);
  cJSON_AddItemToObject(shell, "core", num(sh.core));
  cJSON_AddItemToObject(c, "shell", shell);
  cJSON *d = cJSON_CreateObject();
  if (o && o->vdb_file) {
    cJSON_AddStringToObject(d, "type", "vdb");
    cJSON_AddStringToObject(d, "file", o->vdb_file);
    cJSON_AddStringToObject(d, "grid", o->vdb_grid ? o->vdb_grid : "density");
  } else {
    cJSON_AddStringToObject(d, "type", "procedural");
    cJSON_AddNumberToObject(d, "strands", f->strands);
    cJSON_AddNumberToObject(d, "seed", (double)seed);
    cJSON_AddStringToObject(d, "layout", satf_scene_layout_name(f->layout));
    cJSON_AddItemToObject(d, "strand_width", num(f->strand_width));
    if (f->layout == SATF_SCENE_LAYOUT_GRADIENT)
      cJSON_AddItemToObject(d, "gradient", num(f->gradient));
  }
  cJSON_AddItemToObject(c, "density", d);
  return c;
}

/* The box around every trajectory's control points grown by the largest
 * half-axis (a B-spline stays inside its control points' hull). */
static void fits_bounds(const satf_import_fit *fits, int n, double lo[3],
                        double hi[3]) {
  for (int c = 0; c < 3; c++) {
    lo[c] = DBL_MAX;
    hi[c] = -DBL_MAX;
  }
  for (int i = 0; i < n; i++) {
    double r = 0.0;
    for (int j = 0; j < fits[i].n_radius; j++)
      r = fmax(r, fmax(fits[i].a[j], fits[i].b[j]));
    for (int k = 0; k < fits[i].n_ctrl; k++)
      for (int c = 0; c < 3; c++) {
        lo[c] = fmin(lo[c], fits[i].traj[3 * k + c] - r);
        hi[c] = fmax(hi[c], fits[i].traj[3 * k + c] + r);
      }
  }
}

static cJSON *camera_json(const satf_import_fit *fits, int n) {
  double lo[3], hi[3];
  fits_bounds(fits, n, lo, hi);
  /* the box's diagonal sphere wastes most of the frame on hair that is
   * long and thin; its largest half-extent with a margin frames it */
  double c[3], r = 0.0;
  for (int k = 0; k < 3; k++) {
    c[k] = 0.5 * (lo[k] + hi[k]);
    r = fmax(r, 0.5 * (hi[k] - lo[k]));
  }
  r *= 1.15;
  const double fov = 35.0, pi = 3.14159265358979323846;
  double dist = 1.05 * r / sin(0.5 * fov * pi / 180.0);
  double dir[3] = {0.3, 0.2, 1.0};
  double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  cJSON *cam = cJSON_CreateObject();
  cJSON_AddItemToObject(cam, "position",
                        vec3(c[0] + dist * dir[0] / len,
                             c[1] + dist * dir[1] / len,
                             c[2] + dist * dir[2] / len));
  cJSON_AddItemToObject(cam, "target", vec3(c[0], c[1], c[2]));
  cJSON_AddItemToObject(cam, "up", vec3(0, 1, 0));
  cJSON_AddItemToObject(cam, "fov_y", num(fov));
  return cam;
}

static cJSON *light_json(double dx, double dy, double dz, double r, double g,
                         double b, double intensity) {
  cJSON *l = cJSON_CreateObject();
  cJSON_AddStringToObject(l, "type", "directional");
  cJSON_AddItemToObject(l, "direction", vec3(dx, dy, dz));
  cJSON_AddItemToObject(l, "color", vec3(r, g, b));
  cJSON_AddItemToObject(l, "intensity", num(intensity));
  return l;
}

satf_status satf_import_scene_json(const satf_import_fit *fits, int n,
                                   const satf_import_macro *macro,
                                   const satf_import_scene_options *o,
                                   char **json, satf_error *err) {
  *json = NULL;
  if (n < 1 || (macro && macro->n_clusters != n))
    return satf_error_set(err, SATF_ERR_ARGUMENT,
                          "scene: %d clusters and a macro-cluster table for "
                          "%d",
                          n, macro ? macro->n_clusters : n);
  cJSON *root = cJSON_CreateObject();
  if (!root)
    return satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
  if (o && o->description)
    cJSON_AddStringToObject(root, "description", o->description);
  if (o && o->database)
    cJSON_AddStringToObject(root, "database", o->database);
  if (o && o->mesh_file) { /* drawn opaque, occluding and shadowing hair */
    cJSON *meshes = cJSON_CreateArray(), *mesh = cJSON_CreateObject();
    cJSON_AddStringToObject(mesh, "file", o->mesh_file);
    cJSON_AddItemToArray(meshes, mesh);
    cJSON_AddItemToObject(root, "meshes", meshes);
  }
  cJSON *image = cJSON_CreateObject();
  cJSON_AddNumberToObject(image, "width", o && o->width ? o->width : 640);
  cJSON_AddNumberToObject(image, "height", o && o->height ? o->height : 480);
  cJSON_AddItemToObject(root, "image", image);
  cJSON_AddItemToObject(root, "camera", camera_json(fits, n));
  cJSON *lights = cJSON_CreateArray();
  cJSON_AddItemToArray(lights,
                       light_json(-0.45, -0.6, -0.66, 1.0, 0.97, 0.92, 1.0));
  cJSON_AddItemToArray(lights,
                       light_json(0.8, -0.1, -0.6, 0.75, 0.82, 1.0, 0.3));
  cJSON_AddItemToObject(root, "lights", lights);
  cJSON_AddItemToObject(root, "background", vec3(0.16, 0.17, 0.2));
  cJSON *macros = cJSON_CreateArray();
  int n_macro = macro ? macro->n_macro : n;
  uint64_t seed = o ? o->seed : 1;
  for (int m = 0; m < n_macro; m++) {
    int proto = macro ? macro->prototype[m] : m;
    cJSON *mc = cJSON_CreateObject();
    char name[64];
    snprintf(name, sizeof name, "cluster %d", proto);
    cJSON_AddStringToObject(mc, "name", name);
    cJSON_AddItemToObject(mc, "prototype",
                          cluster_json(&fits[proto], o, seed + (uint64_t)m));
    cJSON *inst = cJSON_CreateArray();
    for (int c = 0; c < n; c++) {
      if ((macro ? macro->macro_of[c] : c) != m)
        continue;
      cJSON *i = cJSON_CreateObject();
      if (c != proto) {
        cJSON_AddItemToObject(i, "matrix",
                              num_array(macro->transform + 16 * (size_t)c, 16));
      }
      cJSON_AddItemToArray(inst, i);
    }
    cJSON_AddItemToObject(mc, "instances", inst);
    cJSON_AddItemToArray(macros, mc);
  }
  cJSON_AddItemToObject(root, "macro_clusters", macros);
  char *text = cJSON_Print(root);
  cJSON_Delete(root);
  if (!text)
    return satf_error_set(err, SATF_ERR_NOMEM, "scene: out of memory");
  *json = text;
  return SATF_OK;
}

satf_status satf_import_write_scene(const char *path,
                                    const satf_import_fit *fits, int n,
                                    const satf_import_macro *macro,
                                    const satf_import_scene_options *o,
                                    satf_error *err) {
  char *text;
  satf_status st = satf_import_scene_json(fits, n, macro, o, &text, err);
  if (st != SATF_OK)
    return st;
  st = satf_write_file_atomic(path, text, strlen(text), err);
  free(text);
  return st;
}
