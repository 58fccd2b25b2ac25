/* satf-view - interactive SATF hair preview in a GLFW window.
 *
 * Left drag orbits the camera, the wheel zooms, right drag moves the key
 * light; keys 1-4 toggle the effects of the paper's Fig. 4, S saves the
 * frame as EXR + PNG, R resets the view, Q or Esc quits. */
#include <stdio.h>
#include <string.h>

#include "frontend.h"
#include "satf/common.h"
#include "satf/gl.h"
#include "viewer.h"

static const char *PROG = "satf-view";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s SCENE.json [--db DB.exr] [options]\n"
      "\n"
      "Interactive SATF hair preview.\n"
      "%s"
      "\n"
      "options:\n"
      "  --db PATH            HRIR database (default: the scene's)\n"
      "  --size WxH           window size (default: the scene's image size)\n"
      "  --samples N          anti-aliasing: N jittered samples per pixel\n"
      "                       (1-64; default: the scene's image.samples, 1);\n"
      "                       costs N times the compositing time\n"
      "  --save-prefix P      saved frames are P-NNNN.exr/.png (default\n"
      "                       satf-view)\n"
      "  --screenshot PATH    render --frames frames, save the window's\n"
      "                       last frame as PATH (.png or .exr), and exit\n"
      "  --frames N           frames before --screenshot (default 3)\n"
      "  --bench N            render N frames of satf-render --bench's\n"
      "                       orbit (or the animation) in the window, print\n"
      "                       the same Table 1 row and exit\n"
      "%s%s%s%s%s"
      "  -h, --help           this help\n",
      PROG, viewer_keys, satf_frontend_shading_help, satf_frontend_effect_help,
      satf_frontend_strand_help, satf_frontend_sparse_help,
      satf_frontend_budget_help);
}

typedef struct options {
  const char *scene_path, *db_path;
  long w, h, samples;
  int strands;
  float strand_width;
  double budget;      /* --memory-budget, bytes (0: the default) */
  int shading;        /* --shading: SATF_MATERIAL_*, -1: the scene's */
  int sparse_strands; /* --sparse-strands N, -1: the default */
  viewer_opts view;
} options;

/* Parses one argument into o; returns -1 after printing an error. */
static int parse_one(satf_cli_args *it, options *o) {
  if (satf_cli_is(it, NULL, "--db"))
    return satf_cli_value(it, &o->db_path);
  if (satf_cli_is(it, NULL, "--size"))
    return satf_cli_value_size(it, 1, 16384, &o->w, &o->h);
  if (satf_cli_is(it, NULL, "--samples"))
    return satf_cli_value_int(it, 1, SATF_SCENE_MAX_SAMPLES, &o->samples);
  if (satf_cli_is(it, NULL, "--save-prefix"))
    return satf_cli_value(it, &o->view.prefix);
  if (satf_cli_is(it, NULL, "--screenshot"))
    return satf_cli_value(it, &o->view.shot);
  if (satf_cli_is(it, NULL, "--frames"))
    return satf_cli_value_int(it, 1, 1000000, &o->view.frames);
  if (satf_cli_is(it, NULL, "--bench"))
    return satf_cli_value_int(it, 1, 100000, &o->view.bench);
  if (satf_cli_is(it, NULL, "--composite")) {
    const char *val;
    if (satf_cli_value(it, &val))
      return -1;
    o->view.composite = satf_frontend_composite(val);
    if (o->view.composite < 0)
      fprintf(stderr, "%s: --composite: expected exact or ordered\n", PROG);
    return o->view.composite < 0 ? -1 : 0;
  }
  if (satf_frontend_effect_flag(it->arg, &o->view.off))
    return 0;
  int budget = satf_frontend_budget_flag(it, &o->budget);
  if (budget != 0)
    return budget < 0 ? -1 : 0;
  int strand = satf_frontend_strand_flag(it, &o->strands, &o->strand_width);
  if (strand != 0)
    return strand < 0 ? -1 : 0;
  int shading = satf_frontend_shading_flag(it, &o->shading);
  if (shading != 0)
    return shading < 0 ? -1 : 0;
  int sparse = satf_frontend_sparse_flag(it, &o->sparse_strands);
  if (sparse != 0)
    return sparse < 0 ? -1 : 0;
  if (!satf_cli_positional(it)) {
    satf_cli_unknown(it);
    return -1;
  }
  if (o->scene_path) {
    fprintf(stderr, "%s: more than one scene\n", PROG);
    return -1;
  }
  o->scene_path = it->arg;
  return 0;
}

/* Returns -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, options *o) {
  memset(o, 0, sizeof *o);
  o->view.off = (satf_scene_effects){1, 1, 1, 1};
  o->shading = -1;
  o->sparse_strands = -1;
  o->view.composite = SATF_COMPOSITE_ORDERED;
  o->view.prefix = "satf-view";
  o->view.frames = 3;
  satf_cli_args it;
  satf_cli_begin(&it, PROG, argc, argv);
  while (satf_cli_next(&it)) {
    if (satf_cli_is(&it, "-h", "--help")) {
      usage(stdout);
      return 0;
    }
    if (parse_one(&it, o))
      return 2;
  }
  if (!o->scene_path) {
    fprintf(stderr, "%s: no scene given (see --help)\n", PROG);
    return 2;
  }
  return -1;
}

int main(int argc, char **argv) {
  options o;
  int rc = parse_args(argc, argv, &o);
  if (rc >= 0)
    return rc;
  satf_frontend fe;
  if (satf_frontend_load(PROG, o.scene_path, o.db_path, o.budget, &o.w, &o.h,
                         &fe) != SATF_OK)
    return 1;
  fe.strand_width = o.strand_width;
  fe.sparse_strands = o.sparse_strands;
  /* the viewer's maps are the renderer's default: the GPU's on a hardware
   * GPU, the CPU's on a software rasteriser */
  /* the source strands before the memory check, which counts them */
  if (satf_frontend_set_shading(PROG, &fe, o.shading) != SATF_OK ||
      (o.strands && satf_frontend_load_strands(PROG, &fe) != SATF_OK) ||
      satf_frontend_check_memory(PROG, &fe, o.w, o.h, SATF_MAPS_DEFAULT) !=
          SATF_OK) {
    satf_frontend_free(&fe);
    return 1;
  }
  if (o.samples > 0)
    fe.scene->image.samples = (int)o.samples;
  const char *base = strrchr(o.scene_path, '/');
  o.view.name = base ? base + 1 : o.scene_path;
  o.view.width = (int)o.w;
  o.view.height = (int)o.h;
  satf_error err;
  satf_error_clear(&err);
  satf_gl_window *win = NULL;
  satf_status st =
      satf_gl_window_create((int)o.w, (int)o.h, "satf-view", &win, &err);
  if (st == SATF_OK)
    st = viewer_run(win, &fe, &o.view, &err);
  if (st != SATF_OK)
    fprintf(stderr, "%s: %s\n", PROG, err.message);
  satf_gl_window_destroy(win);
  satf_frontend_free(&fe);
#if !defined(__SANITIZE_ADDRESS__)
  /* Under AddressSanitizer, glfwTerminate unloads Mesa's GLX driver and
   * LeakSanitizer then blames its allocations on an unknown module. */
  if (win)
    satf_gl_window_terminate();
#endif
  return st == SATF_OK ? 0 : 1;
}
