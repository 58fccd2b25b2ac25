/* satf-view - interactive SATF hair preview in a GLFW window.
 *
 * Left drag orbits the camera, the wheel zooms, right drag moves the key
 * light; keys 1-4 toggle the effects of the paper's Fig. 4, S saves the
 * frame as EXR + PNG, R resets the view, Q or Esc quits. */
#include "satf/gl.h" /* before GLFW, which must not pull in GL/gl.h */
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "satf/common.h"
#include "frontend.h"
#include "satf/scene.h"

static const char *PROG = "satf-view";

static void usage(FILE *out) {
  fprintf(
      out,
      "usage: %s SCENE.json [--db DB.exr] [options]\n"
      "\n"
      "Interactive SATF hair preview.\n"
      "  mouse: left drag orbit, wheel zoom, right drag move the key light\n"
      "  keys:  1 SATF maps  2 secondary highlight  3 self-shadow\n"
      "         space pause/play the animation, left/right step a frame\n"
      "         4 cluster shadows  O exact/ordered compositing\n"
      "         S save frame (EXR + PNG)  R reset view\n"
      "         Q / Esc quit\n"
      "\n"
      "options:\n"
      "  --db PATH            HRIR database (default: the scene's)\n"
      "  --size WxH           window size (default: the scene's image size)\n"
      "  --save-prefix P      saved frames are P-NNNN.exr/.png (default\n"
      "                       satf-view)\n"
      "  --screenshot PATH    render --frames frames, save the window's\n"
      "                       last frame as PATH (.png or .exr), and exit\n"
      "  --frames N           frames before --screenshot (default 3)\n"
      "%s"
      "  -h, --help           this help\n",
      PROG, satf_frontend_effect_help);
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
  case GLFW_KEY_O:
    satf_renderer_set_composite(v->r, satf_renderer_composite(v->r) ==
                                              SATF_COMPOSITE_EXACT
                                          ? SATF_COMPOSITE_ORDERED
                                          : SATF_COMPOSITE_EXACT);
    break;
  case GLFW_KEY_R: reset_view(v); break;
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

/* Reads the window's back buffer and writes it (sRGB bytes already, so the
 * PNG gets them as linear-encoded values converted back). */
static satf_status save_frame(satf_renderer *r, int w, int h, const char *base,
                              satf_error *err) {
  satf_image *img = NULL;
  satf_frame_timing t;
  char exr[1100], png[1100];
  snprintf(exr, sizeof exr, "%s.exr", base);
  snprintf(png, sizeof png, "%s.png", base);
  satf_status st = satf_renderer_render_image(r, 0, &img, &t, err);
  if (st == SATF_OK)
    st = satf_image_write_exr(img, exr, err);
  if (st == SATF_OK) {
    satf_image *rgb = NULL;
    const char *names[3] = {"R", "G", "B"};
    st = satf_image_create(w, h, names, 3, &rgb, err);
    for (int c = 0; c < 3 && st == SATF_OK; c++)
      memcpy(satf_image_plane(rgb, c), satf_image_const_plane(img, c),
             (size_t)w * (size_t)h * sizeof(float));
    if (st == SATF_OK)
      st = satf_image_write_png(rgb, png, err);
    satf_image_destroy(rgb);
  }
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

int main(int argc, char **argv) {
  const char *scene_path = NULL, *db_path = NULL, *shot = NULL;
  long w = 0, h = 0, frames = 3;
  satf_scene_effects off = {1, 1, 1, 1};
  int composite = SATF_COMPOSITE_ORDERED;
  viewer v;
  memset(&v, 0, sizeof v);
  satf_scene *snap = NULL; /* the animation frame on screen */
  v.prefix = "satf-view";
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
    int needs = !strcmp(a, "--db") || !strcmp(a, "--size") ||
                !strcmp(a, "--save-prefix") || !strcmp(a, "--screenshot") ||
                !strcmp(a, "--frames") || !strcmp(a, "--composite");
    if (needs && !val) {
      fprintf(stderr, "%s: %s needs a value (see --help)\n", PROG, a);
      return 2;
    }
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
      usage(stdout);
      return 0;
    } else if (!strcmp(a, "--db")) {
      db_path = argv[++i];
    } else if (!strcmp(a, "--size")) {
      if (satf_cli_size(PROG, a, argv[++i], 16, 8192, &w, &h))
        return 2;
    } else if (!strcmp(a, "--save-prefix")) {
      v.prefix = argv[++i];
    } else if (!strcmp(a, "--screenshot")) {
      shot = argv[++i];
    } else if (!strcmp(a, "--composite")) {
      composite = satf_frontend_composite(argv[++i]);
      if (composite < 0) {
        fprintf(stderr, "%s: --composite: expected exact or ordered\n", PROG);
        return 2;
      }
    } else if (!strcmp(a, "--frames")) {
      if (satf_cli_int(PROG, a, argv[++i], 1, 1000000, &frames))
        return 2;
    } else if (satf_frontend_effect_flag(a, &off)) {
    } else if (a[0] == '-') {
      fprintf(stderr, "%s: unknown option '%s' (see --help)\n", PROG, a);
      return 2;
    } else if (!scene_path) {
      scene_path = a;
    } else {
      fprintf(stderr, "%s: more than one scene\n", PROG);
      return 2;
    }
  }
  if (!scene_path) {
    fprintf(stderr, "%s: no scene given (see --help)\n", PROG);
    return 2;
  }
  satf_frontend fe;
  if (satf_frontend_load(PROG, scene_path, db_path, &w, &h, &fe) != SATF_OK)
    return 1;
  satf_error err;
  satf_error_clear(&err);
  int rc = 1;
  satf_gl_window *win = NULL;
  if (satf_gl_window_create((int)w, (int)h, "satf-view", &win, &err) != SATF_OK)
    goto done;
  int fw, fh;
  satf_gl_window_framebuffer_size(win, &fw, &fh);
  if (satf_renderer_create(fe.scene, fe.db, fw > 0 ? fw : (int)w,
                           fh > 0 ? fh : (int)h, 0, &v.r, &err) != SATF_OK)
    goto done;
  satf_frontend_apply(v.r, &off, composite);
  satf_scene_effects *e = satf_renderer_effects(v.r);
  v.home = *satf_renderer_camera(v.r);
  reset_view(&v);
  satf_scene_light *key = satf_renderer_light(v.r, 0);
  if (key) {
    float d[3];
    if (key->type == SATF_SCENE_LIGHT_POINT)
      for (int a = 0; a < 3; a++)
        d[a] = v.home.target[a] - key->position[a];
    else
      memcpy(d, key->direction, sizeof d);
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    v.light_pitch = asinf(len > 0 ? -d[1] / len : 0.0f);
    v.light_yaw = atan2f(-d[0], -d[2]);
  }
  GLFWwindow *gw = satf_gl_window_glfw(win);
  glfwSetWindowUserPointer(gw, &v);
  glfwSetKeyCallback(gw, on_key);
  glfwSetMouseButtonCallback(gw, on_button);
  glfwSetCursorPosCallback(gw, on_cursor);
  glfwSetScrollCallback(gw, on_scroll);
  double fps_t0 = satf_now_seconds(), fps = 0.0;
  int fps_frames = 0;
  long frame = 0;
  satf_frame_timing t;
  memset(&t, 0, sizeof t);
  v.animated = satf_scene_frame_range(fe.scene, &v.first, &v.last);
  v.fps = satf_scene_fps(fe.scene);
  int shown = -1;
  double last_tick = satf_now_seconds();
  while (!satf_gl_window_should_close(win)) {
    satf_gl_window_framebuffer_size(win, &fw, &fh);
    if (fw <= 0 || fh <= 0) { /* minimised: nothing to draw */
      glfwWaitEventsTimeout(0.1);
      last_tick = satf_now_seconds();
      continue;
    }
    if (v.animated) {
      /* real-time playback: the frame follows the clock, so frames are
       * dropped when rendering is slower than the animation's rate */
      double now = satf_now_seconds(), span = v.last - v.first + 1;
      if (!v.paused)
        v.clock += (now - last_tick) * v.fps;
      last_tick = now;
      v.clock += v.step;
      v.step = 0;
      v.clock -= span * floor(v.clock / span);
      int want = v.first + (int)v.clock;
      if (want != shown) {
        satf_scene *next = NULL;
        satf_scene_camera cam = *satf_renderer_camera(v.r);
        satf_scene_light key = *satf_renderer_light(v.r, 0);
        if (satf_scene_at_frame(fe.scene, want, &next, &err) != SATF_OK ||
            satf_renderer_set_scene(v.r, next, NULL, &err) != SATF_OK) {
          satf_scene_destroy(next);
          goto done;
        }
        if (v.user_camera)
          *satf_renderer_camera(v.r) = cam;
        if (v.user_light)
          *satf_renderer_light(v.r, 0) = key;
        satf_scene_destroy(snap);
        snap = next;
        shown = want;
      }
    }
    if (satf_renderer_resize(v.r, fw, fh, &err) != SATF_OK ||
        satf_renderer_render(v.r, SATF_AOV_BEAUTY, &t, &err) != SATF_OK)
      goto done;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fw, fh);
    satf_renderer_present(v.r);
    frame++;
    if (shot && frame >= frames) {
      glFinish();
      if (screenshot(fw, fh, shot, &err) != SATF_OK)
        goto done;
      fprintf(stderr, "%s: wrote %s\n", PROG, shot);
      break;
    }
    satf_gl_window_swap(win);
    if (v.save_requested) {
      char base[1024];
      snprintf(base, sizeof base, "%s-%04d", v.prefix, v.saved++);
      v.save_requested = 0;
      if (save_frame(v.r, fw, fh, base, &err) != SATF_OK)
        fprintf(stderr, "%s: %s\n", PROG, err.message);
    }
    fps_frames++;
    double now = satf_now_seconds();
    if (now - fps_t0 > 0.5) {
      fps = fps_frames / (now - fps_t0);
      fps_t0 = now;
      fps_frames = 0;
      char title[384], anim[96] = "";
      if (v.animated)
        snprintf(anim, sizeof anim, " | frame %d/%d%s (%.0f fps)", shown,
                 v.last, v.paused ? " paused" : "", v.fps);
      snprintf(
          title, sizeof title,
          "satf-view  %.1f FPS%s | I %.1f C %.1f M %.1f L %.1f S %.1f ms | "
          "[1]satf %s [2]specII %s [3]self-shadow %s [4]cluster shadows %s "
          "[O]%s",
          fps, anim, t.index_ms, t.maps_ms, t.upload_ms, t.lighting_ms,
          t.shadow_ms, e->satf ? "on" : "off",
          e->secondary_highlight ? "on" : "off", e->self_shadow ? "on" : "off",
          e->cluster_shadows ? "on" : "off",
          satf_renderer_composite(v.r) == SATF_COMPOSITE_EXACT ? "exact"
                                                               : "ordered");
      glfwSetWindowTitle(gw, title);
    }
    satf_gl_window_poll(win);
  }
  rc = 0;
done:
  if (snap) { /* the renderer reads the snapshot until it is destroyed */
    satf_renderer_destroy(v.r);
    v.r = NULL;
    satf_scene_destroy(snap);
  }
  if (rc != 0)
    fprintf(stderr, "%s: %s\n", PROG, err.message);
  satf_renderer_destroy(v.r);
  satf_gl_window_destroy(win);
  satf_frontend_free(&fe);
#if !defined(__SANITIZE_ADDRESS__)
  /* Under AddressSanitizer, glfwTerminate unloads Mesa's GLX driver and
   * LeakSanitizer then blames its allocations on an unknown module. */
  if (win)
    satf_gl_window_terminate();
#endif
  return rc;
}
