/* satf-render - headless SATF rendering to OpenEXR (and PNG) through EGL. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "frontend.h"
#include "satf/common.h"
#include "satf/gl.h"
#include "satf/render.h"
#include "satf/scene.h"
#ifdef SATF_MPI
#include "mpi_frames.h"
#endif

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
      "  -o, --output PATH    OpenEXR frame: R, G, B, A half, colour\n"
      "                       premultiplied over transparent black (ready\n"
      "                       to composite over a plate); with --aov also\n"
      "                       diffuse.R/G/B, specI.R/G/B, specII.R/G/B,\n"
      "                       shadow.Y, alpha.Y and Z (float: distance\n"
      "                       along the view axis, 1e10 where empty)\n"
      "  --png PATH           sRGB PNG preview, over the scene's background\n"
      "  --background-in-exr  composite the EXR's R, G, B over the scene's\n"
      "                       background too (A kept)\n"
      "  --db PATH            HRIR database (default: the scene's "
      "\"database\")\n"
      "  --size WxH           image size (default: the scene's, else "
      "640x480)\n"
      "  --aov                also write the AOV layers\n"
      "  --frames A-B|N|all   render animation frames A to B (all: the "
      "scene's\n"
      "                       range); -o and --png are then patterns such as\n"
      "                       out/frame_%%04d.exr; under mpirun the ranks\n"
      "                       share the frames (frame A+k: rank k mod N)\n"
      "  --resume             with --frames: skip frames already written\n"
      "  --contact-sheet PNG  with --frames: thumbnails of every frame\n"
      "  --export-mesh PATH   write every shell layer mesh as\n"
      "                       PATH-m<macro>-l<layer>.obj or .ply (OpenMesh)\n"
      "  --bench N            render N frames of an orbiting camera (of the\n"
      "                       animation, if the scene has one) and print\n"
      "                       the paper's Table 1 row (ms per stage, FPS)\n"
      "  --threads N          CPU threads for the map stage (the CPU's maps;\n"
      "                       0 = all)\n"
      "  --samples N          anti-aliasing: N jittered samples per pixel\n"
      "                       (1-64; default: the scene's image.samples, 1)\n"
      "  --pixel-filter F     auto (default), box or blackman-harris: the\n"
      "                       film filter across hair drawn as strands;\n"
      "                       blackman-harris is Cycles' default (a faint\n"
      "                       fringe on thin hair, about twice the\n"
      "                       strands' cost); auto takes it for hair of at\n"
      "                       most 1000 strands, the box for denser hair\n"
      "  --lod on|off         level of detail by size on screen: clusters a\n"
      "                       few pixels wide read fewer shell layers and\n"
      "                       draw coarser proxies, faded without popping\n"
      "                       (default off: within soft IoU 0.97, SSIM 0.95\n"
      "                       of full detail on every sample, but no faster\n"
      "                       on llvmpipe yet; zoomed-out fur drifts)\n"
      "  --maps cpu|gpu|auto  where the maps are built when the eye or a\n"
      "                       light moves: cpu, looked up on the CPU and\n"
      "                       uploaded (the reference); gpu, a compute\n"
      "                       pass from the database kept on the GPU (the\n"
      "                       same maps, the physical mode's too; no\n"
      "                       look-up or upload on the CPU); auto, gpu on\n"
      "                       a hardware GPU and cpu on a software\n"
      "                       rasteriser such as llvmpipe (default %s)\n"
      "  --shadow-move T|off  keep the cluster shadows' deep opacity map\n"
      "                       while no cluster moved more than T of its\n"
      "                       texels or slabs since it was drawn (default\n"
      "                       1, the shadow filter's reach; off: drawn\n"
      "                       again every animation frame)\n"
      "%s%s%s%s%s"
      "  -q, --quiet          no summary\n"
      "  -h, --help           this help\n",
      PROG, satf_maps_mode_name(SATF_MAPS_DEFAULT), satf_frontend_shading_help,
      satf_frontend_effect_help, satf_frontend_strand_help,
      satf_frontend_sparse_help, satf_frontend_budget_help);
}

typedef struct options {
  const char *scene_path, *db_path, *exr, *png, *mesh_path, *frames, *sheet;
  long w, h, bench, threads, samples;
  int resume, aov, quiet, composite, bg_in_exr, strands, lod;
  int pixel_filter;    /* satf_pixel_filter */
  satf_maps_mode maps; /* --maps */
  int interrupted;     /* --frames stopped by a signal (render_frames) */
  float shadow_move;   /* --shadow-move, -1: off, NAN: not given */
  float strand_width;
  double budget;      /* --memory-budget, bytes (0: the default) */
  double estimate;    /* the memory estimate, bytes (printed beside the peak) */
  int shading;        /* --shading: SATF_MATERIAL_*, -1: the scene's */
  int sparse_strands; /* --sparse-strands N, -1: the default */
  satf_scene_effects off;
#ifdef SATF_MPI
  const satf_mpi *mpi; /* the job's ranks share --frames */
#endif
} options;

/* An option that takes a path, or NULL. */
static const char **path_option(satf_cli_args *it, options *o) {
  if (satf_cli_is(it, "-o", "--output"))
    return &o->exr;
  if (satf_cli_is(it, NULL, "--png"))
    return &o->png;
  if (satf_cli_is(it, NULL, "--frames"))
    return &o->frames;
  if (satf_cli_is(it, NULL, "--contact-sheet"))
    return &o->sheet;
  if (satf_cli_is(it, NULL, "--export-mesh"))
    return &o->mesh_path;
  if (satf_cli_is(it, NULL, "--db"))
    return &o->db_path;
  return NULL;
}

/* Parses one argument into o; returns -1 after printing an error. */
static int parse_one(satf_cli_args *it, options *o) {
  const char **path = path_option(it, o), *val;
  int strand;
  if (path)
    return satf_cli_value(it, path);
  if (satf_cli_is(it, NULL, "--size"))
    return satf_cli_value_size(it, 1, 16384, &o->w, &o->h);
  if (satf_cli_is(it, NULL, "--bench"))
    return satf_cli_value_int(it, 1, 100000, &o->bench);
  if (satf_cli_is(it, NULL, "--threads"))
    return satf_cli_value_int(it, 0, 1024, &o->threads);
  if (satf_cli_is(it, NULL, "--samples"))
    return satf_cli_value_int(it, 1, SATF_SCENE_MAX_SAMPLES, &o->samples);
  if (satf_cli_is(it, NULL, "--lod")) {
    if (satf_cli_value(it, &val))
      return -1;
    o->lod = !strcmp(val, "on") ? 1 : !strcmp(val, "off") ? 0 : -1;
    if (o->lod < 0)
      fprintf(stderr, "%s: --lod: expected on or off, got '%s'\n", PROG, val);
    return o->lod < 0 ? -1 : 0;
  }
  if (satf_cli_is(it, NULL, "--maps")) {
    if (satf_cli_value(it, &val))
      return -1;
    if (satf_maps_mode_parse(val, &o->maps) == 0)
      return 0;
    fprintf(stderr, "%s: --maps: expected cpu, gpu or auto, got '%s'\n", PROG,
            val);
    return -1;
  }
  if (satf_cli_is(it, NULL, "--shadow-move")) {
    if (satf_cli_value(it, &val))
      return -1;
    char *end = NULL;
    double t = strtod(val, &end);
    if (!strcmp(val, "off"))
      t = -1.0;
    else if (end == val || *end || !(t >= 0.0 && t <= 1e6)) {
      fprintf(stderr,
              "%s: --shadow-move: expected texels >= 0 or off, got "
              "'%s'\n",
              PROG, val);
      return -1;
    }
    o->shadow_move = (float)t;
    return 0;
  }
  if (satf_cli_is(it, NULL, "--pixel-filter")) {
    if (satf_cli_value(it, &val))
      return -1;
    o->pixel_filter = !strcmp(val, "auto")  ? SATF_PIXEL_FILTER_AUTO
                      : !strcmp(val, "box") ? SATF_PIXEL_FILTER_BOX
                      : !strcmp(val, "blackman-harris")
                          ? SATF_PIXEL_FILTER_BLACKMAN_HARRIS
                          : -1;
    if (o->pixel_filter >= 0)
      return 0;
    fprintf(stderr,
            "%s: --pixel-filter: expected auto, box or blackman-harris, got "
            "'%s'\n",
            PROG, val);
    return -1;
  }
  if (satf_cli_is(it, NULL, "--composite")) {
    if (satf_cli_value(it, &val))
      return -1;
    o->composite = satf_frontend_composite(val);
    if (o->composite < 0)
      fprintf(stderr, "%s: --composite: expected exact or ordered, got '%s'\n",
              PROG, val);
    return o->composite < 0 ? -1 : 0;
  }
  if (satf_cli_is(it, NULL, "--resume"))
    o->resume = 1;
  else if (satf_cli_is(it, NULL, "--aov"))
    o->aov = 1;
  else if (satf_cli_is(it, NULL, "--background-in-exr"))
    o->bg_in_exr = 1;
  else if (satf_cli_is(it, "-q", "--quiet"))
    o->quiet = 1;
  else if (satf_frontend_effect_flag(it->arg, &o->off))
    return 0;
  else if ((strand = satf_frontend_budget_flag(it, &o->budget)) != 0)
    return strand < 0 ? -1 : 0;
  else if ((strand = satf_frontend_shading_flag(it, &o->shading)) != 0)
    return strand < 0 ? -1 : 0;
  else if ((strand = satf_frontend_sparse_flag(it, &o->sparse_strands)) != 0)
    return strand < 0 ? -1 : 0;
  else if ((strand = satf_frontend_strand_flag(it, &o->strands,
                                               &o->strand_width)) != 0)
    return strand < 0 ? -1 : 0;
  else if (!satf_cli_positional(it)) {
    satf_cli_unknown(it);
    return -1;
  } else if (!o->scene_path)
    o->scene_path = it->arg;
  else {
    fprintf(stderr, "%s: more than one scene ('%s', '%s')\n", PROG,
            o->scene_path, it->arg);
    return -1;
  }
  return 0;
}

/* Checks that the options make a job. */
static int check_args(const options *o) {
  if (!o->scene_path) {
    fprintf(stderr, "%s: no scene given (see --help)\n", PROG);
    return 2;
  }
  if ((o->resume || o->sheet) && !o->frames) {
    fprintf(stderr, "%s: --resume and --contact-sheet go with --frames\n",
            PROG);
    return 2;
  }
  if (!o->exr && !o->png && !o->bench && !o->mesh_path && !o->sheet) {
    fprintf(stderr,
            "%s: nothing to do: give -o FRAME.exr, --png, --bench or "
            "--export-mesh\n",
            PROG);
    return 2;
  }
  satf_file_role files[] = {{"the scene", o->scene_path, 0},
                            {"--db", o->db_path, 0},
                            {"-o", o->exr, 1},
                            {"--png", o->png, 1},
                            {"--contact-sheet", o->sheet, 1}};
  satf_error err;
  if (satf_check_distinct_files(files, 5, &err) != SATF_OK ||
      satf_check_output_extension("-o", o->exr, ".exr", "an OpenEXR image",
                                  &err) ||
      satf_check_output_extension("--png", o->png, ".png", "a PNG image",
                                  &err) ||
      satf_check_output_extension("--contact-sheet", o->sheet, ".png",
                                  "a PNG image", &err)) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    return 2;
  }
  return -1;
}

/* Returns -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, options *o) {
  memset(o, 0, sizeof *o);
  o->off = (satf_scene_effects){1, 1, 1, 1};
  o->shading = -1;
  o->sparse_strands = -1;
  o->composite = SATF_COMPOSITE_EXACT;
  o->lod = 0;
  o->pixel_filter = SATF_PIXEL_FILTER_AUTO;
  o->maps = SATF_MAPS_DEFAULT;
  o->shadow_move = NAN;
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
  return check_args(o);
}

/* The range in this process, or its share under mpirun. */
static satf_status render_range(const options *o, satf_renderer *r,
                                const satf_scene *scene,
                                const satf_sequence_opts *so,
                                satf_sequence_stats *ss, satf_error *err) {
#ifdef SATF_MPI
  if (o->mpi->size > 1)
    return satf_mpi_frames(o->mpi, PROG, r, scene, so, ss, err);
#else
  (void)o;
#endif
  return satf_sequence_render(r, scene, so, ss, err);
}

/* Ctrl-C (or a TERM) during --frames: the batch stops after the frame it
 * is on, which is written whole, and says where it got to; a second one
 * ends the program at once. */
static volatile sig_atomic_t stop_frames;

static void on_stop(int sig) {
  (void)sig;
  stop_frames = 1;
  static const char msg[] =
      "\nsatf-render: stopping after this frame (again to quit now)\n";
  ssize_t w = write(STDERR_FILENO, msg, sizeof msg - 1);
  (void)w;
}

static void catch_stop(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_stop;
  sa.sa_flags = SA_RESETHAND; /* the second signal takes the default */
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

/* --frames: the range through the sequence renderer; -o and --png were
 * patterns and are done afterwards. */
static satf_status render_frames(options *o, satf_renderer *r,
                                 const satf_scene *scene, satf_error *err) {
  satf_sequence_opts so = {
      0,         0,      o->exr,   o->png,       o->sheet,
      o->resume, o->aov, o->quiet, o->bg_in_exr, &stop_frames};
  satf_sequence_stats ss;
  satf_status st =
      satf_frontend_frame_range(scene, o->frames, &so.first, &so.last, err);
  catch_stop();
  if (st == SATF_OK)
    st = render_range(o, r, scene, &so, &ss, err);
  if (st != SATF_OK)
    return st;
  if (ss.interrupted) { /* what is done is on disk: the job ends there */
    int total = so.last - so.first + 1, done = ss.rendered + ss.skipped;
    fprintf(stderr,
            "%s: interrupted: frames %d-%d: %d of %d finished (%d rendered "
            "now, %d already complete), %d left; the same command with "
            "--resume continues from there\n",
            PROG, so.first, so.last, done, total, ss.rendered, ss.skipped,
            total - done);
    o->interrupted = 1;
    o->exr = o->png = NULL;
    return SATF_OK;
  }
  if (!o->quiet)
    printf("%s: frames %d-%d: %d rendered, %d already complete, %.1f s "
           "(%.1f ms a frame: I %.1f C %.1f M %.1f L %.1f S %.1f)\n",
           PROG, so.first, so.last, ss.rendered, ss.skipped, ss.seconds,
           ss.mean.total_ms, ss.mean.index_ms, ss.mean.maps_ms,
           ss.mean.upload_ms, ss.mean.lighting_ms, ss.mean.shadow_ms);
  o->exr = o->png = NULL;
  return SATF_OK;
}

static satf_status export_meshes(const options *o, satf_renderer *r,
                                 satf_error *err) {
  int files = 0;
  satf_status st = satf_renderer_export_meshes(r, o->mesh_path, &files, err);
  if (st == SATF_OK && !o->quiet)
    printf("%s: wrote %d layer meshes (%s)\n", PROG, files, o->mesh_path);
  return st;
}

/* One frame to -o (EXR) and --png. */
static satf_status render_still(const options *o, satf_renderer *r,
                                const satf_render_stats *stats, double t_setup,
                                satf_error *err) {
  satf_image *img = NULL;
  satf_frame_timing t;
  satf_status st = satf_renderer_render_image(r, o->aov, &img, &t, err);
  if (st == SATF_OK && o->bg_in_exr)
    satf_image_flatten(img); /* the PNG preview is the same either way */
  satf_render_stats frame;   /* overflow of this frame */
  satf_renderer_stats(r, &frame);
  if (st == SATF_OK && o->exr)
    st = satf_image_write_exr(img, o->exr, err);
  if (st == SATF_OK && o->png)
    st = satf_image_write_png_rgb(img, o->png, err);
  satf_image_destroy(img);
  if (st == SATF_OK && !o->quiet)
    printf("%s: %s%s%s: %ldx%ld, %ld clusters, %ld layers, %.1fK HSVs, "
           "%ld look-ups, %.1fM fragments, %ld pixels over 64 fragments "
           "(nearest kept), frame %.1f ms (set-up %.2f s, peak memory %.0f MB, "
           "estimated %.0f MB)\n",
           PROG, o->exr ? o->exr : "", o->exr && o->png ? " + " : "",
           o->png ? o->png : "", o->w, o->h, stats->clusters, stats->layers,
           stats->hsvs / 1000.0, t.lookups, t.fragments / 1e6,
           frame.overflow_pixels, t.total_ms, t_setup, satf_peak_memory_mb(),
           o->estimate / 1e6);
  if (st == SATF_OK && !o->quiet && satf_renderer_strand_count(r) > 0)
    printf("%s: drawn: the scene's %d source strands, not its clusters "
           "(--strands)\n",
           PROG, satf_renderer_strand_count(r));
  return st;
}

/* --bench N: prints the Table 1 row. */
static satf_status bench(const options *o, const satf_gl_context *ctx,
                         satf_renderer *r, const satf_scene *scene,
                         const satf_render_stats *stats, double t_setup,
                         satf_error *err) {
  satf_frame_timing mean;
  double fps;
  satf_status st =
      satf_frontend_bench(r, scene, o->bench, NULL, NULL, &mean, &fps, err);
  if (st != SATF_OK)
    return st;
  const char *base = strrchr(o->scene_path, '/');
  satf_frontend_table_header(stdout);
  satf_frontend_table_row(stdout, base ? base + 1 : o->scene_path, stats, &mean,
                          fps);
  /* what the frame costs beyond Table 1's columns, at the starting view:
   * the fragments the exact composite stores (the shading pass's work; the
   * ordered composite blends without counting them) and the look-ups of a
   * frame after the camera moved and of one where nothing changed */
  satf_frame_timing moved, still;
  /* L by pass: its shells, the strands among them and the resolve, timed
   * apart (waiting for the GPU between them) only for these frames, so
   * the row above is the frame as it runs */
  satf_renderer_set_pass_timing(r, 1);
  st = satf_renderer_render(r, SATF_AOV_BEAUTY, &moved, err);
  if (st == SATF_OK)
    st = satf_renderer_render(r, SATF_AOV_BEAUTY, &still, err);
  satf_renderer_set_pass_timing(r, 0);
  if (st != SATF_OK)
    return st;
  double px = (double)o->w * (double)o->h;
  if (satf_renderer_composite(r) == SATF_COMPOSITE_EXACT)
    printf("fragments %ld (%.2f per pixel)", still.fragments,
           (double)still.fragments / px);
  else
    printf("fragments - (ordered)");
  printf("; look-ups %ld after a move, %ld when still (%.1f ms C)\n",
         moved.lookups, still.lookups, still.maps_ms);
  if (still.shells_ms + still.strands_ms + still.resolve_ms > 0.0)
    printf("L by pass %.1f ms: shells %.1f, strands among them %.1f, "
           "resolve %.1f, the rest (clears, meshes, counts) %.1f\n",
           still.lighting_ms, still.shells_ms, still.strands_ms,
           still.resolve_ms,
           still.lighting_ms - still.shells_ms - still.strands_ms -
               still.resolve_ms);
  /* clusters per level of detail at the starting view (lod.c) */
  satf_render_stats now;
  satf_renderer_stats(r, &now);
  if (!satf_renderer_lod(r))
    printf("LOD off: every cluster at full detail\n");
  else
    printf("LOD mix: %ld full, %ld 1/2, %ld 1/4, %ld 1/8 or less of the "
           "layers; %ld as one layer, %ld with a coarse proxy\n",
           now.lod_levels[0], now.lod_levels[1], now.lod_levels[2],
           now.lod_levels[3], now.lod_single, now.lod_coarse);
  /* which machine the figures are of: llvmpipe and a GPU differ 10x */
  int major = 0, minor = 0;
  satf_gl_context_version(ctx, &major, &minor);
  if (satf_renderer_maps(r) == SATF_MAPS_GPU)
    printf("GL %d.%d on %s; the maps built on the GPU\n", major, minor,
           satf_gl_context_renderer(ctx));
  else
    printf("GL %d.%d on %s; %d CPU threads for the maps\n", major, minor,
           satf_gl_context_renderer(ctx),
           o->threads > 0 ? (int)o->threads : satf_cpu_count());
  printf("set-up %.2f s (the renderer's creation), peak memory %.0f MB "
         "(estimated %.0f MB)\n",
         t_setup, satf_peak_memory_mb(), o->estimate / 1e6);
  return SATF_OK;
}

static satf_status run(options *o, const satf_frontend *fe, satf_error *err) {
  satf_gl_context *ctx = NULL;
  satf_renderer *r = NULL;
  double t0 = satf_now_seconds();
  satf_status st =
      satf_gl_context_create_headless((int)o->w, (int)o->h, &ctx, err);
  if (st == SATF_OK)
    st = satf_frontend_create_renderer(fe, (int)o->w, (int)o->h,
                                       (int)o->threads, o->quiet, &r, err);
  double t_setup = satf_now_seconds() - t0;
  satf_render_stats stats; /* of the scene as loaded */
  if (st == SATF_OK) {
    satf_frontend_apply(r, &o->off, o->composite);
    satf_renderer_set_pixel_filter(r, (satf_pixel_filter)o->pixel_filter);
    satf_renderer_set_lod(r, o->lod);
    st = satf_renderer_set_maps(r, o->maps, err);
  }
  if (st == SATF_OK) {
    if (!isnan(o->shadow_move))
      satf_renderer_set_shadow_move(r, o->shadow_move);
    satf_renderer_stats(r, &stats);
    st = satf_frontend_apply_strands(r, fe, err);
  }
  if (st == SATF_OK && o->frames)
    st = render_frames(o, r, fe->scene, err);
  if (st == SATF_OK && o->mesh_path)
    st = export_meshes(o, r, err);
  if (st == SATF_OK && (o->exr || o->png))
    st = render_still(o, r, &stats, t_setup, err);
  if (st == SATF_OK && o->bench)
    st = bench(o, ctx, r, fe->scene, &stats, t_setup, err);
  satf_frontend_maps_note(PROG, r);
  satf_renderer_destroy(r);
  satf_gl_context_destroy(ctx);
  return st;
}

/* The job after the arguments: load, render, report. */
static int render_job(options *o) {
  satf_frontend fe;
  if (satf_frontend_load(PROG, o->scene_path, o->db_path, o->budget, &o->w,
                         &o->h, &fe) != SATF_OK)
    return 1;
  fe.strand_width = o->strand_width;
  fe.sparse_strands = o->sparse_strands;
  /* the source strands before the memory check, which counts them */
  if (satf_frontend_set_shading(PROG, &fe, o->shading) != SATF_OK ||
      (o->strands && satf_frontend_load_strands(PROG, &fe) != SATF_OK) ||
      satf_frontend_check_memory(PROG, &fe, o->w, o->h, o->maps) != SATF_OK) {
    satf_frontend_free(&fe);
    return 1;
  }
  o->estimate = fe.memory_estimate;
  if (o->samples > 0)
    fe.scene->image.samples = (int)o->samples;
  satf_error err;
  satf_error_clear(&err);
  int rc = 0;
  if (run(o, &fe, &err) != SATF_OK) {
    fprintf(stderr, "%s: %s\n", PROG, err.message);
    rc = 1;
  } else if (o->interrupted) {
    rc = 130; /* as a shell reports a job ended by Ctrl-C */
  }
  satf_frontend_free(&fe);
  return rc;
}

#ifdef SATF_MPI
/* Under mpirun the ranks share --frames and nothing else; ranks other than
 * 0 stay quiet. Returns -1 to go on, else the exit status. */
static int mpi_options(options *o, const satf_mpi *m) {
  o->mpi = m;
  if (m->size == 1)
    return -1;
  if (!o->frames || o->bench || o->mesh_path) {
    if (m->rank == 0)
      fprintf(stderr,
              "%s: under mpirun the ranks share the frames of --frames A-B; "
              "--bench, --export-mesh and single frames run in one process\n",
              PROG);
    return 2;
  }
  if (m->rank != 0)
    o->quiet = 1;
  return -1;
}

int main(int argc, char **argv) {
  satf_mpi m;
  if (satf_mpi_start(PROG, &argc, &argv, &m) != 0)
    return 1;
  int muted[2];
  satf_mpi_mute(&m, muted); /* --help and argument errors print once */
  options o;
  int rc = parse_args(argc, argv, &o);
  if (rc < 0)
    rc = mpi_options(&o, &m);
  satf_mpi_unmute(muted);
  if (rc < 0)
    rc = render_job(&o);
  if (rc == 1 && m.size > 1)
    satf_mpi_fail(&m, PROG, "this rank failed (see above)");
  rc = satf_mpi_share_status(&m, rc); /* waits for rank 0's contact sheet */
  satf_mpi_stop(&m);
  return rc;
}
#else
int main(int argc, char **argv) {
  options o;
  int rc = parse_args(argc, argv, &o);
  return rc >= 0 ? rc : render_job(&o);
}
#endif
