/* satf-render - headless SATF rendering to OpenEXR (and PNG) through EGL. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "frontend.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "satf/scene.h"

static const char *PROG = "satf-render";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s SCENE.json [--db DB.exr] -o FRAME.exr [options]\n"
      "\n"
      "Renders a hair scene with the SATF method (EGL surfaceless, no X "
      "needed).\n"
      "\n"
      "options:\n"
      "  -o, --output PATH    OpenEXR frame (RGBA half; with --aov also\n"
      "                       diffuse, specI, specII, shadow, alpha)\n"
      "  --png PATH           sRGB PNG preview\n"
      "  --db PATH            HRIR database (default: the scene's "
      "\"database\")\n"
      "  --size WxH           image size (default: the scene's, else "
      "640x480)\n"
      "  --aov                also write the AOV layers\n"
      "  --frames A-B|N|all   render animation frames A to B (all: the "
      "scene's\n"
      "                       range); -o and --png are then patterns such as\n"
      "                       out/frame_%%04d.exr\n"
      "  --resume             with --frames: skip frames already written\n"
      "  --contact-sheet PNG  with --frames: thumbnails of every frame\n"
      "  --export-mesh PATH   write every shell layer mesh as\n"
      "                       PATH-m<macro>-l<layer>.obj or .ply (OpenMesh)\n"
      "  --bench N            render N frames of an orbiting camera (of the\n"
      "                       animation, if the scene has one) and print\n"
      "                       the paper's Table 1 row (ms per stage, FPS)\n"
      "  --threads N          CPU threads for the map stage (0 = all)\n"
      "%s"
      "  -q, --quiet          no summary\n"
      "  -h, --help           this help\n",
      PROG, satf_frontend_effect_help);
}

static void orbit(satf_scene_camera *cam, const satf_scene_camera *start,
                  float angle) {
  /* rotate the eye about the up axis through the target (Rodrigues) */
  float v[3], k[3] = {start->up[0], start->up[1], start->up[2]};
  for (int a = 0; a < 3; a++)
    v[a] = start->position[a] - start->target[a];
  float c = cosf(angle), s = sinf(angle);
  float kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  float kx[3] = {k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2],
                 k[0] * v[1] - k[1] * v[0]};
  for (int a = 0; a < 3; a++)
    cam->position[a] =
        start->target[a] + v[a] * c + kx[a] * s + k[a] * kv * (1 - c);
}

int main(int argc, char **argv) {
  const char *scene_path = NULL, *db_path = NULL, *exr = NULL, *png = NULL;
  const char *mesh_path = NULL, *frames = NULL, *sheet = NULL;
  int resume = 0;
  long w = 0, h = 0, bench = 0, threads = 0;
  int aov = 0, quiet = 0;
  satf_scene_effects off = {1, 1, 1, 1};
  int composite = SATF_COMPOSITE_EXACT;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED_VALUE                                                             \
  if (!val) {                                                                  \
    fprintf(stderr, "%s: %s needs a value (see --help)\n", PROG, a);           \
    return 2;                                                                  \
  }                                                                            \
  i++;
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      usage(stdout);
      return 0;
    } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
      NEED_VALUE exr = val;
    } else if (!strcmp(a, "--png")) {
      NEED_VALUE png = val;
    } else if (!strcmp(a, "--frames")) {
      NEED_VALUE frames = val;
    } else if (!strcmp(a, "--contact-sheet")) {
      NEED_VALUE sheet = val;
    } else if (!strcmp(a, "--resume")) {
      resume = 1;
    } else if (!strcmp(a, "--export-mesh")) {
      NEED_VALUE mesh_path = val;
    } else if (!strcmp(a, "--db")) {
      NEED_VALUE db_path = val;
    } else if (!strcmp(a, "--size")) {
      NEED_VALUE if (satf_cli_size(PROG, a, val, 16, 8192, &w, &h)) return 2;
    } else if (!strcmp(a, "--bench")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 1, 100000, &bench)) return 2;
    } else if (!strcmp(a, "--threads")) {
      NEED_VALUE if (satf_cli_int(PROG, a, val, 0, 1024, &threads)) return 2;
    } else if (!strcmp(a, "--composite")) {
      NEED_VALUE composite = satf_frontend_composite(val);
      if (composite < 0) {
        fprintf(stderr,
                "%s: --composite: expected exact or ordered, got '%s'\n", PROG,
                val);
        return 2;
      }
    } else if (!strcmp(a, "--aov")) {
      aov = 1;
    } else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) {
      quiet = 1;
    } else if (satf_frontend_effect_flag(a, &off)) {
    } else if (a[0] == '-') {
      fprintf(stderr, "%s: unknown option '%s' (see --help)\n", PROG, a);
      return 2;
    } else if (!scene_path) {
      scene_path = a;
    } else {
      fprintf(stderr, "%s: more than one scene ('%s', '%s')\n", PROG,
              scene_path, a);
      return 2;
    }
#undef NEED_VALUE
  }
  if (!scene_path) {
    fprintf(stderr, "%s: no scene given (see --help)\n", PROG);
    return 2;
  }
  if ((resume || sheet) && !frames) {
    fprintf(stderr, "%s: --resume and --contact-sheet go with --frames\n",
            PROG);
    return 2;
  }
  if (!exr && !png && !bench && !mesh_path && !sheet) {
    fprintf(stderr,
            "%s: nothing to do: give -o FRAME.exr, --png, --bench or "
            "--export-mesh\n",
            PROG);
    return 2;
  }
  satf_frontend fe;
  if (satf_frontend_load(PROG, scene_path, db_path, &w, &h, &fe) != SATF_OK)
    return 1;
  satf_error err;
  satf_error_clear(&err);
  int rc = 1;
  satf_gl_context *ctx = NULL;
  satf_renderer *r = NULL;
  satf_image *img = NULL;
  double t0 = satf_now_seconds();
  if (satf_gl_context_create_headless((int)w, (int)h, &ctx, &err) != SATF_OK ||
      satf_renderer_create(fe.scene, fe.db, (int)w, (int)h, (int)threads, &r,
                           &err) != SATF_OK)
    goto done;
  double t_setup = satf_now_seconds() - t0;
  satf_frontend_apply(r, &off, composite);
  satf_render_stats stats;
  satf_renderer_stats(r, &stats);
  if (frames) {
    satf_sequence_opts so = {0, 0, exr, png, sheet, resume, aov, quiet};
    char tail = 0;
    if (!strcmp(frames, "all")) {
      satf_scene_frame_range(fe.scene, &so.first, &so.last);
    } else if (sscanf(frames, "%d-%d%c", &so.first, &so.last, &tail) != 2) {
      if (sscanf(frames, "%d%c", &so.first, &tail) != 1) {
        satf_error_set(&err, SATF_ERR_ARGUMENT,
                       "--frames: expected A-B, N or all, got '%s'", frames);
        goto done;
      }
      so.last = so.first;
    }
    satf_sequence_stats ss;
    if (satf_sequence_render(r, fe.scene, &so, &ss, &err) != SATF_OK)
      goto done;
    if (!quiet)
      printf("%s: frames %d-%d: %d rendered, %d already complete, %.1f s "
             "(%.1f ms a frame: I %.1f C %.1f M %.1f L %.1f S %.1f)\n",
             PROG, so.first, so.last, ss.rendered, ss.skipped, ss.seconds,
             ss.mean.total_ms, ss.mean.index_ms, ss.mean.maps_ms,
             ss.mean.upload_ms, ss.mean.lighting_ms, ss.mean.shadow_ms);
    exr = png = NULL; /* they were patterns, now done */
  }
  if (mesh_path) {
    int files = 0;
    if (satf_renderer_export_meshes(r, mesh_path, &files, &err) != SATF_OK)
      goto done;
    if (!quiet)
      printf("%s: wrote %d layer meshes (%s)\n", PROG, files, mesh_path);
  }
  satf_frame_timing t;
  if (exr || png) {
    if (satf_renderer_render_image(r, aov, &img, &t, &err) != SATF_OK)
      goto done;
    if (exr && satf_image_write_exr(img, exr, &err) != SATF_OK)
      goto done;
    if (png) {
      /* the PNG shows the composite over the background, opaque */
      satf_image *rgb = NULL;
      const char *names[3] = {"R", "G", "B"};
      if (satf_image_create((int)w, (int)h, names, 3, &rgb, &err) != SATF_OK)
        goto done;
      for (int c = 0; c < 3; c++)
        memcpy(satf_image_plane(rgb, c),
               satf_image_const_plane(img,
                                      satf_image_channel_index(img, names[c])),
               (size_t)w * (size_t)h * sizeof(float));
      satf_status st = satf_image_write_png(rgb, png, &err);
      satf_image_destroy(rgb);
      if (st != SATF_OK)
        goto done;
    }
    if (!quiet)
      printf("%s: %s%s%s: %ldx%ld, %ld clusters, %ld layers, %.1fK HSVs, "
             "%ld look-ups, %.1fM fragments, frame %.1f ms (set-up %.2f s)\n",
             PROG, exr ? exr : "", exr && png ? " + " : "", png ? png : "", w,
             h, stats.clusters, stats.layers, stats.hsvs / 1000.0, t.lookups,
             t.fragments / 1e6, t.total_ms, t_setup);
  }
  if (bench) {
    satf_scene_camera start = *satf_renderer_camera(r);
    satf_frame_timing sum;
    memset(&sum, 0, sizeof sum);
    /* one warm-up frame, then N timed frames over a full orbit */
    if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
      goto done;
    int first = 0, last = 0;
    int animated = satf_scene_frame_range(fe.scene, &first, &last);
    satf_scene *snap = NULL;
    double b0 = satf_now_seconds();
    for (long f = 0; f < bench; f++) {
      double s0 = satf_now_seconds();
      if (animated) { /* play the animation: moving clusters are rebuilt */
        satf_scene *next = NULL;
        double frame = first + (double)(f % (last - first + 1));
        satf_status st = satf_scene_at_frame(fe.scene, frame, &next, &err);
        if (st == SATF_OK)
          st = satf_renderer_set_scene(r, next, NULL, &err);
        satf_scene_destroy(snap);
        snap = next;
        if (st != SATF_OK)
          break;
      } else {
        orbit(satf_renderer_camera(r), &start,
              6.2831853f * (float)f / (float)bench);
      }
      double s1 = satf_now_seconds();
      if (satf_renderer_render(r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
        break;
      /* interpolating the frame and rebuilding moving clusters counts as
       * index calculation (Table 1's I) */
      t.index_ms += 1e3 * (s1 - s0);
      sum.index_ms += t.index_ms / (double)bench;
      sum.maps_ms += t.maps_ms / (double)bench;
      sum.upload_ms += t.upload_ms / (double)bench;
      sum.lighting_ms += t.lighting_ms / (double)bench;
      sum.shadow_ms += t.shadow_ms / (double)bench;
    }
    double fps = (double)bench / (satf_now_seconds() - b0);
    if (snap) {
      satf_error ignore;
      satf_renderer_set_scene(r, fe.scene, NULL, &ignore);
      satf_scene_destroy(snap);
    }
    if (err.status != SATF_OK)
      goto done;
    *satf_renderer_camera(r) = start;
    const char *base = strrchr(scene_path, '/');
    satf_frontend_table_header(stdout);
    satf_frontend_table_row(stdout, base ? base + 1 : scene_path, &stats, &sum,
                            fps);
  }
  rc = 0;
done:
  if (rc != 0)
    fprintf(stderr, "%s: %s\n", PROG, err.message);
  satf_image_destroy(img);
  satf_renderer_destroy(r);
  satf_gl_context_destroy(ctx);
  satf_frontend_free(&fe);
  return rc;
}
