/* viewer.c - see viewer.h. */
#include "viewer.h" /* satf/gl.h before GLFW, which must not pull in GL/gl.h */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "satf/scene.h"

static const char *PROG = "satf-view";

const char viewer_keys[] =
    "  mouse: left drag orbit, wheel zoom, right drag move the key light\n"
    "  keys:  1 SATF maps  2 secondary highlight  3 self-shadow\n"
    "         space pause/play the animation, left/right step a frame\n"
    "         4 cluster shadows  O exact/ordered compositing\n"
    "         S save frame (EXR + PNG)  R reset view\n"
    "         T the source strands (the reference) / the clusters\n"
    "         H these keys (here and in the title)  Q / Esc quit\n";

static void print_keys(void) {
  printf("satf-view:\n%s", viewer_keys);
  fflush(stdout);
}

typedef struct viewer {
  satf_renderer *r;
  satf_scene_camera home;
  float yaw, pitch, dist;       /* camera about its target */
  float light_yaw, light_pitch; /* key light direction */
  int dragging, light_dragging;
  double mx, my;
  int save_requested, saved;
  const char *prefix;
  /* animation playback */
  int animated, first, last, paused, step;
  double fps, clock;           /* the animation time, in frames since `first` */
  int user_camera, user_light; /* moved by hand: the animation keeps off */
  const satf_scene *scene;     /* the scene as loaded (animated) */
  satf_scene *snap;            /* the animation frame on screen */
  int shown;                   /* its frame number, -1 before the first */
  double last_tick;            /* when the clock last advanced */
  /* the frame rate in the title */
  double fps_t0;
  int fps_frames;
  satf_frame_timing t; /* of the last frame */
  /* T: the strand reference (the scene's source strands) in turn with the
   * clusters, to judge the preview against what it approximates */
  satf_frontend *fe;
  int toggle_strands;
  int show_keys; /* H: the title lists the keys */
} viewer;

static void place_camera(viewer *v) {
  satf_scene_camera *c = satf_renderer_camera(v->r);
  float cp = cosf(v->pitch);
  c->position[0] = c->target[0] + v->dist * cp * sinf(v->yaw);
  c->position[1] = c->target[1] + v->dist * sinf(v->pitch);
  c->position[2] = c->target[2] + v->dist * cp * cosf(v->yaw);
  c->up[0] = 0;
  c->up[1] = 1;
  c->up[2] = 0;
}

static void place_light(viewer *v) {
  satf_scene_light *l = satf_renderer_light(v->r, 0);
  if (!l)
    return;
  float cp = cosf(v->light_pitch);
  float d[3] = {-cp * sinf(v->light_yaw), -sinf(v->light_pitch),
                -cp * cosf(v->light_yaw)};
  if (l->type == SATF_SCENE_LIGHT_POINT) {
    const float *t = satf_renderer_camera(v->r)->target;
    for (int a = 0; a < 3; a++)
      l->position[a] = t[a] - 3.0f * v->dist * d[a];
  } else {
    memcpy(l->direction, d, sizeof d);
  }
}

static void reset_view(viewer *v) {
  *satf_renderer_camera(v->r) = v->home;
  const satf_scene_camera *c = &v->home;
  float d[3] = {c->position[0] - c->target[0], c->position[1] - c->target[1],
                c->position[2] - c->target[2]};
  v->dist = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  v->yaw = atan2f(d[0], d[2]);
  v->pitch = asinf(v->dist > 0 ? d[1] / v->dist : 0.0f);
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods) {
  (void)scancode;
  (void)mods;
  if (action != GLFW_PRESS)
    return;
  viewer *v = glfwGetWindowUserPointer(w);
  satf_scene_effects *e = satf_renderer_effects(v->r);
  switch (key) {
  case GLFW_KEY_1: e->satf = !e->satf; break;
  case GLFW_KEY_2: e->secondary_highlight = !e->secondary_highlight; break;
  case GLFW_KEY_3: e->self_shadow = !e->self_shadow; break;
  case GLFW_KEY_4: e->cluster_shadows = !e->cluster_shadows; break;
  case GLFW_KEY_S: v->save_requested = 1; break;
  case GLFW_KEY_T: v->toggle_strands = 1; break;
  case GLFW_KEY_O:
    satf_renderer_set_composite(v->r, satf_renderer_composite(v->r) ==
                                              SATF_COMPOSITE_EXACT
                                          ? SATF_COMPOSITE_ORDERED
                                          : SATF_COMPOSITE_EXACT);
    break;
  case GLFW_KEY_R: reset_view(v); break;
  case GLFW_KEY_H:
    v->show_keys = !v->show_keys;
    if (v->show_keys)
      print_keys();
    break;
  case GLFW_KEY_SPACE: v->paused = !v->paused; break;
  case GLFW_KEY_RIGHT:
    v->paused = 1;
    v->step = 1;
    break;
  case GLFW_KEY_LEFT:
    v->paused = 1;
    v->step = -1;
    break;
  case GLFW_KEY_Q:
  case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
  default: break;
  }
}

static void on_button(GLFWwindow *w, int button, int action, int mods) {
  (void)mods;
  viewer *v = glfwGetWindowUserPointer(w);
  glfwGetCursorPos(w, &v->mx, &v->my);
  if (button == GLFW_MOUSE_BUTTON_LEFT)
    v->dragging = action == GLFW_PRESS;
  if (button == GLFW_MOUSE_BUTTON_RIGHT)
    v->light_dragging = action == GLFW_PRESS;
}

static void on_cursor(GLFWwindow *w, double x, double y) {
  viewer *v = glfwGetWindowUserPointer(w);
  float dx = (float)(x - v->mx) * 0.01f, dy = (float)(y - v->my) * 0.01f;
  v->mx = x;
  v->my = y;
  if (v->dragging) {
    v->user_camera = 1;
    v->yaw -= dx;
    v->pitch += dy;
    v->pitch = fmaxf(-1.5f, fminf(1.5f, v->pitch));
    place_camera(v);
  }
  if (v->light_dragging) {
    v->user_light = 1;
    v->light_yaw -= dx;
    v->light_pitch = fmaxf(-1.5f, fminf(1.5f, v->light_pitch + dy));
    place_light(v);
  }
}

static void on_scroll(GLFWwindow *w, double dx, double dy) {
  (void)dx;
  viewer *v = glfwGetWindowUserPointer(w);
  v->user_camera = 1;
  v->dist *= powf(0.9f, (float)dy);
  place_camera(v);
}

/* Renders the frame again and writes it as BASE.exr and BASE.png. */
static satf_status save_frame(satf_renderer *r, const char *base,
                              satf_error *err) {
  satf_image *img = NULL;
  satf_frame_timing t;
  char exr[1100], png[1100];
  snprintf(exr, sizeof exr, "%s.exr", base);
  snprintf(png, sizeof png, "%s.png", base);
  satf_status st = satf_renderer_render_image(r, 0, &img, &t, err);
  if (st == SATF_OK)
    st = satf_image_write_exr(img, exr, err);
  if (st == SATF_OK)
    st = satf_image_write_png_rgb(img, png, err);
  satf_image_destroy(img);
  if (st == SATF_OK)
    fprintf(stderr, "%s: saved %s and %s\n", PROG, exr, png);
  return st;
}

/* The displayed frame from the back buffer, for --screenshot. */
static satf_status screenshot(int w, int h, const char *path, satf_error *err) {
  size_t n = (size_t)w * (size_t)h * 4;
  float *buf = malloc(n * sizeof(float));
  if (!buf)
    return satf_error_set(err, SATF_ERR_NOMEM, "out of memory");
  satf_status st = satf_gl_read_rgba_bottom_up(0, GL_BACK, w, h, buf, n, err);
  satf_image *img = NULL;
  const char *names[3] = {"R", "G", "B"};
  if (st == SATF_OK)
    st = satf_image_create(w, h, names, 3, &img, err);
  if (st == SATF_OK) {
    /* the window shows sRGB-encoded values; undo the encoding so the file
     * holds linear values like satf-render's */
    for (size_t i = 0; i < n; i++) {
      float x = buf[i];
      buf[i] = x <= 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
    }
    const char *const src[4] = {"R", "G", "B", NULL}; /* alpha dropped */
    st = satf_image_store_interleaved(img, buf, 4, src, SATF_ROWS_BOTTOM_UP,
                                      err);
  }
  size_t len = strlen(path);
  if (st == SATF_OK)
    st = len > 4 && !strcmp(path + len - 4, ".exr")
             ? satf_image_write_exr(img, path, err)
             : satf_image_write_png(img, path, err);
  satf_image_destroy(img);
  free(buf);
  return st;
}

/* Points the key light's angles at its direction in the scene. */
static void aim_light_angles(viewer *v) {
  satf_scene_light *key = satf_renderer_light(v->r, 0);
  if (!key)
    return;
  float d[3];
  if (key->type == SATF_SCENE_LIGHT_POINT)
    for (int a = 0; a < 3; a++)
      d[a] = v->home.target[a] - key->position[a];
  else
    memcpy(d, key->direction, sizeof d);
  float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  v->light_pitch = asinf(len > 0 ? -d[1] / len : 0.0f);
  v->light_yaw = atan2f(-d[0], -d[2]);
}

/* Creates the renderer at the window's framebuffer size and hooks the
 * window's input to v. */
static satf_status viewer_init(viewer *v, satf_gl_window *win,
                               satf_frontend *fe, const viewer_opts *o,
                               satf_error *err) {
  memset(v, 0, sizeof *v);
  v->fe = fe;
  v->prefix = o->prefix;
  v->scene = fe->scene;
  v->shown = -1;
  int fw, fh;
  satf_gl_window_framebuffer_size(win, &fw, &fh);
  satf_status st = satf_frontend_create_renderer(
      fe, fw > 0 ? fw : o->width, fh > 0 ? fh : o->height, 0, 0, &v->r, err);
  if (st != SATF_OK)
    return st;
  satf_frontend_apply(v->r, &o->off, o->composite);
  if ((st = satf_frontend_apply_strands(v->r, fe, err)) != SATF_OK)
    return st;
  v->home = *satf_renderer_camera(v->r);
  reset_view(v);
  aim_light_angles(v);
  GLFWwindow *gw = satf_gl_window_glfw(win);
  glfwSetWindowUserPointer(gw, v);
  glfwSetKeyCallback(gw, on_key);
  glfwSetMouseButtonCallback(gw, on_button);
  glfwSetCursorPosCallback(gw, on_cursor);
  glfwSetScrollCallback(gw, on_scroll);
  v->fps_t0 = satf_now_seconds();
  v->animated = satf_scene_frame_range(fe->scene, &v->first, &v->last);
  v->fps = satf_scene_fps(fe->scene);
  v->last_tick = satf_now_seconds();
  return SATF_OK;
}

/* Real-time playback: the frame follows the clock, so frames are dropped
 * when rendering is slower than the animation's rate. */
static satf_status advance_animation(viewer *v, satf_error *err) {
  double now = satf_now_seconds(), span = v->last - v->first + 1;
  if (!v->paused)
    v->clock += (now - v->last_tick) * v->fps;
  v->last_tick = now;
  v->clock += v->step;
  v->step = 0;
  v->clock -= span * floor(v->clock / span);
  int want = v->first + (int)v->clock;
  if (want == v->shown)
    return SATF_OK;
  satf_scene *next = NULL;
  satf_scene_camera cam = *satf_renderer_camera(v->r);
  satf_scene_light key = *satf_renderer_light(v->r, 0);
  satf_status st = satf_scene_at_frame(v->scene, want, &next, err);
  if (st == SATF_OK)
    st = satf_renderer_set_scene(v->r, next, NULL, err);
  if (st != SATF_OK) {
    satf_scene_destroy(next);
    return st;
  }
  if (v->user_camera)
    *satf_renderer_camera(v->r) = cam;
  if (v->user_light)
    *satf_renderer_light(v->r, 0) = key;
  satf_scene_destroy(v->snap);
  v->snap = next;
  v->shown = want;
  return SATF_OK;
}

/* Every half second: the frame rate, stage times and switches. */
static void update_title(viewer *v, GLFWwindow *gw) {
  v->fps_frames++;
  double now = satf_now_seconds();
  if (!(now - v->fps_t0 > 0.5))
    return;
  double fps = v->fps_frames / (now - v->fps_t0);
  v->fps_t0 = now;
  v->fps_frames = 0;
  const satf_scene_effects *e = satf_renderer_effects(v->r);
  const satf_frame_timing *t = &v->t;
  char title[384], anim[96] = "";
  if (v->animated)
    snprintf(anim, sizeof anim, " | frame %d/%d%s (%.0f fps)", v->shown,
             v->last, v->paused ? " paused" : "", v->fps);
  snprintf(title, sizeof title,
           "satf-view  %.1f FPS%s | I %.1f C %.1f M %.1f L %.1f S %.1f ms | "
           "[1]satf %s [2]specII %s [3]self-shadow %s [4]cluster shadows %s "
           "[O]%s [T]%s",
           fps, anim, t->index_ms, t->maps_ms, t->upload_ms, t->lighting_ms,
           t->shadow_ms, e->satf ? "on" : "off",
           e->secondary_highlight ? "on" : "off", e->self_shadow ? "on" : "off",
           e->cluster_shadows ? "on" : "off",
           satf_renderer_composite(v->r) == SATF_COMPOSITE_EXACT ? "exact"
                                                                 : "ordered",
           satf_renderer_strand_count(v->r) > 0 ? "strands" : "clusters");
  if (v->show_keys)
    snprintf(title, sizeof title,
             "satf-view keys (H hides them): drag orbit, wheel zoom, right "
             "drag light | 1 maps 2 specII 3 self-shadow 4 cluster shadows O "
             "compositing T strands | S save R reset space play left/right "
             "step Q quit");
  glfwSetWindowTitle(gw, title);
}

/* T: the clusters give way to the scene's source strands, or back. The
 * strands are read the first time; a scene without them (not made by
 * satf-import) says so and keeps the clusters. */
static satf_status toggle_strands(viewer *v, satf_error *err) {
  v->toggle_strands = 0;
  if (satf_renderer_strand_count(v->r) > 0)
    return satf_renderer_set_strands(v->r, 0, NULL, NULL, NULL, 0.0f, err);
  if (!v->fe->strands && satf_frontend_load_strands(PROG, v->fe) != SATF_OK)
    return SATF_OK; /* printed; the clusters stay */
  return satf_frontend_apply_strands(v->r, v->fe, err);
}

/* Draws frame number `frame` at fw x fh; sets *done once the screenshot is
 * written. */
static satf_status draw(viewer *v, satf_gl_window *win, const viewer_opts *o,
                        long frame, int fw, int fh, int *done,
                        satf_error *err) {
  satf_status st = v->animated ? advance_animation(v, err) : SATF_OK;
  if (st == SATF_OK && v->toggle_strands)
    st = toggle_strands(v, err);
  if (st == SATF_OK)
    st = satf_renderer_resize(v->r, fw, fh, err);
  if (st == SATF_OK)
    st = satf_renderer_render(v->r, SATF_AOV_BEAUTY, &v->t, err);
  if (st != SATF_OK)
    return st;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fw, fh);
  satf_renderer_present(v->r);
  if (o->shot && frame >= o->frames) {
    glFinish();
    st = screenshot(fw, fh, o->shot, err);
    if (st == SATF_OK)
      fprintf(stderr, "%s: wrote %s\n", PROG, o->shot);
    *done = 1;
    return st;
  }
  satf_gl_window_swap(win);
  if (v->save_requested) {
    char base[1024];
    snprintf(base, sizeof base, "%s-%04d", v->prefix, v->saved++);
    v->save_requested = 0;
    if (save_frame(v->r, base, err) != SATF_OK)
      fprintf(stderr, "%s: %s\n", PROG, err->message);
  }
  update_title(v, satf_gl_window_glfw(win));
  return SATF_OK;
}

/* One benchmark frame on screen: what the interactive loop does after
 * rendering (present, swap, events), so the row is the viewer's rate. */
typedef struct bench_window {
  viewer *v;
  satf_gl_window *win;
} bench_window;

static satf_status bench_present(void *ctx, satf_error *err) {
  (void)err;
  bench_window *b = ctx;
  int fw, fh;
  satf_gl_window_framebuffer_size(b->win, &fw, &fh);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, fw, fh);
  satf_renderer_present(b->v->r);
  satf_gl_window_swap(b->win);
  satf_gl_window_poll(b->win);
  return SATF_OK;
}

/* --bench N: satf-render --bench's orbit and row, drawn in the window. */
static satf_status bench(viewer *v, satf_gl_window *win,
                         const satf_frontend *fe, const viewer_opts *o,
                         satf_error *err) {
  satf_render_stats stats;
  satf_renderer_stats(v->r, &stats);
  bench_window b = {v, win};
  satf_frame_timing mean;
  double fps;
  satf_status st = satf_frontend_bench(v->r, fe->scene, o->bench, bench_present,
                                       &b, &mean, &fps, err);
  if (st != SATF_OK)
    return st;
  satf_frontend_table_header(stdout);
  satf_frontend_table_row(stdout, o->name, &stats, &mean, fps);
  int fw, fh;
  satf_gl_window_framebuffer_size(win, &fw, &fh);
  printf("in a %dx%d window (satf-view): each frame presented and swapped; "
         "the maps built on the %s\n",
         fw, fh, satf_renderer_maps(v->r) == SATF_MAPS_GPU ? "GPU" : "CPU");
  return SATF_OK;
}

satf_status viewer_run(satf_gl_window *win, satf_frontend *fe,
                       const viewer_opts *opts, satf_error *err) {
  viewer v;
  satf_status st = viewer_init(&v, win, fe, opts, err);
  if (st == SATF_OK && opts->bench > 0) {
    st = bench(&v, win, fe, opts, err);
    satf_renderer_destroy(v.r);
    return st;
  }
  if (st == SATF_OK)
    print_keys();
  long frame = 0;
  int done = 0;
  while (st == SATF_OK && !done && !satf_gl_window_should_close(win)) {
    int fw, fh;
    satf_gl_window_framebuffer_size(win, &fw, &fh);
    if (fw <= 0 || fh <= 0) { /* minimised: nothing to draw */
      glfwWaitEventsTimeout(0.1);
      v.last_tick = satf_now_seconds();
      continue;
    }
    st = draw(&v, win, opts, ++frame, fw, fh, &done, err);
    if (st == SATF_OK && !done)
      satf_gl_window_poll(win);
  }
  satf_frontend_maps_note(PROG, v.r);
  /* the renderer reads the snapshot until it is destroyed */
  satf_renderer_destroy(v.r);
  satf_scene_destroy(v.snap);
  return st;
}
