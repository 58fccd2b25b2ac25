/* lists.c - owns the per-pixel fragment arrays (lists.h): their textures
 * and framebuffer, their binding for a fill pass and the counts read back
 * after one. */
#include "lists.h"

#include <stdlib.h>

#include "shaders.h"

satf_status lists_alloc(frag_lists *l, int slots, satf_error *err) {
  if (l->counts)
    glDeleteTextures(1, &l->counts);
  if (l->frags)
    glDeleteTextures(1, &l->frags);
  if (l->keys) /* made again, at the new size, when a frame needs it */
    glDeleteTextures(1, &l->keys);
  l->keys = 0;
  glGenTextures(1, &l->counts);
  glBindTexture(GL_TEXTURE_2D, l->counts);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32UI, l->width, l->height);
  glGenTextures(1, &l->frags);
  glBindTexture(GL_TEXTURE_2D_ARRAY, l->frags);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA32UI, l->width, l->height,
                 slots);
  l->slots = slots;
  return satf_gl_check("fragment arrays", err);
}

/* The nearest passes' depth mask, its framebuffer and its program. */
static satf_status mask_attach(frag_lists *l, satf_error *err) {
  if (l->mask)
    glDeleteTextures(1, &l->mask);
  glGenTextures(1, &l->mask);
  glBindTexture(GL_TEXTURE_2D, l->mask);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, l->width, l->height);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  if (!l->mask_fbo)
    glGenFramebuffers(1, &l->mask_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, l->mask_fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D,
                         l->mask, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!l->mask_vao)
    glGenVertexArrays(1, &l->mask_vao);
  if (l->mask_prog)
    return satf_gl_check("overflow mask", err);
  return shaders_program("overflow mask", satf_glsl_fullscreen_vs,
                         satf_glsl_overflow_mask_fs, "", &l->mask_prog, err);
}

satf_status lists_alloc_keys(frag_lists *l, satf_error *err) {
  if (l->keys)
    return SATF_OK;
  glGenTextures(1, &l->keys);
  glBindTexture(GL_TEXTURE_2D_ARRAY, l->keys);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_R32UI, l->width, l->height,
                 l->slots + 1);
  satf_status st = satf_gl_check("fragment depth keys", err);
  /* the mask at the arrays' size, made with the keys: a renderer whose
   * frames never overflow compiles no program for it */
  return st == SATF_OK ? mask_attach(l, err) : st;
}

static int pool_capacity(int width, int height) {
  long n = (long)width * height;
  return n < LISTS_POOL_MAX ? (int)n : LISTS_POOL_MAX;
}

/* The pool and the heads at the frame's size. */
static satf_status pool_alloc(frag_lists *l, satf_error *err) {
  if (l->heads)
    glDeleteTextures(1, &l->heads);
  if (l->pool_buf)
    glDeleteBuffers(1, &l->pool_buf);
  glGenTextures(1, &l->heads);
  glBindTexture(GL_TEXTURE_2D, l->heads);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32UI, l->width, l->height);
  l->pool = pool_capacity(l->width, l->height);
  GLuint header[4] = {0, (GLuint)l->pool, 0, 0};
  glGenBuffers(1, &l->pool_buf);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, l->pool_buf);
  glBufferData(GL_SHADER_STORAGE_BUFFER, 16 * ((GLsizeiptr)l->pool + 1), NULL,
               GL_DYNAMIC_COPY);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof header, header);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  l->pool_dirty = 1; /* the heads hold nothing defined yet */
  return satf_gl_check("fragment pool", err);
}

void lists_begin(frag_lists *l) {
  /* a frame that overflowed nothing left the pool empty: clearing it
   * anyway stalled on the last frame's resolve (hair_7a's shading 10-20%
   * slower) */
  if (!l->pool_dirty)
    return;
  GLuint zero = 0;
  glClearTexImage(l->heads, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, l->pool_buf);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zero, &zero);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  l->pool_dirty = 0;
}

int lists_pool_held(const frag_lists *l) {
  GLuint count = 0xFFFFFFFFu;
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, l->pool_buf);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof count, &count);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  return count <= (GLuint)l->pool;
}

satf_status lists_attach(frag_lists *l, int width, int height, GLuint depth,
                         satf_error *err) {
  l->width = width;
  l->height = height;
  l->depth = depth;
  satf_status st = pool_alloc(l, err);
  if (st != SATF_OK)
    return st;
  if (!l->fbo)
    glGenFramebuffers(1, &l->fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, l->fbo);
  glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_WIDTH, width);
  glFramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_DEFAULT_HEIGHT,
                          height);
  /* the hair's fragment pass tests against the meshes' depth */
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D,
                         depth, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return lists_alloc(l, l->slots > 0 ? l->slots : START_SLOTS, err);
}

void lists_release(frag_lists *l) {
  GLuint texs[5] = {l->counts, l->frags, l->keys, l->mask, l->heads};
  glDeleteTextures(5, texs);
  if (l->pool_buf)
    glDeleteBuffers(1, &l->pool_buf);
  l->pool_buf = l->heads = 0;
  GLuint fbos[2] = {l->fbo, l->mask_fbo};
  glDeleteFramebuffers(2, fbos);
  if (l->mask_vao)
    glDeleteVertexArrays(1, &l->mask_vao);
  if (l->mask_prog)
    glDeleteProgram(l->mask_prog);
  l->counts = l->frags = l->keys = l->fbo = 0;
  l->mask = l->mask_fbo = l->mask_vao = l->mask_prog = 0;
}

satf_status lists_grow(frag_lists *l, int slots, int *grown, satf_error *err) {
  *grown = 0;
  if (slots <= l->slots || l->slots >= SATF_MAX_FRAGMENTS)
    return SATF_OK;
  satf_status st = lists_alloc(
      l, slots < SATF_MAX_FRAGMENTS ? slots : SATF_MAX_FRAGMENTS, err);
  *grown = st == SATF_OK;
  return st;
}

void lists_bind(const frag_lists *l, int mode) {
  GLuint zero = 0, empty = 0xFFFFFFFFu;
  if (mode == 0) /* the nearest passes redo only pixels it overflowed */
    glClearTexImage(l->counts, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindImageTexture(3, l->heads, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, l->pool_buf);
  glBindImageTexture(0, l->counts, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  glBindImageTexture(1, l->frags, 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32UI);
  if (mode == 1) /* no key yet: every slot farther than any fragment */
    glClearTexImage(l->keys, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
  if (mode > 0)
    glBindImageTexture(2, l->keys, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
  glBindFramebuffer(GL_FRAMEBUFFER, mode > 0 ? l->mask_fbo : l->fbo);
  glViewport(0, 0, l->width, l->height);
}

void lists_mask_overflow(const frag_lists *l) {
  glBindFramebuffer(GL_FRAMEBUFFER, l->mask_fbo);
  glViewport(0, 0, l->width, l->height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glUseProgram(l->mask_prog);
  glBindImageTexture(0, l->counts, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, l->depth);
  glUniform1i(glGetUniformLocation(l->mask_prog, "u_depth"), 0);
  glUniform1i(glGetUniformLocation(l->mask_prog, "u_slots"), l->slots);
  shaders_fullscreen(l->mask_vao);
  glBindTexture(GL_TEXTURE_2D, 0);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_TEST);
}

/* From the top down: `deeper` pixels of more than s fragments, `sum` their
 * fragments, so sum - s deeper past s slots. */
int lists_slots_within(const GLuint *counts, size_t n, long room) {
  enum { TOP = SATF_MAX_FRAGMENTS };
  long hist[TOP + 2] = {0}, over_n = 0, over_sum = 0;
  for (size_t i = 0; i < n; i++) {
    GLuint c = counts[i];
    if (c > TOP) { /* all past any slot count: counted whole */
      over_n++;
      over_sum += (long)c;
    } else
      hist[c]++;
  }
  long deeper = over_n, sum = over_sum;
  int best = TOP;
  for (int s = TOP; s >= START_SLOTS; s--) {
    /* deeper, sum: the pixels of more than s fragments */
    if (sum - (long)s * deeper > room)
      break;
    best = s;
    deeper += hist[s];
    sum += (long)s * hist[s];
  }
  return best;
}

GLuint lists_count(frag_lists *l, int nearest, long *fragments,
                   long *overflow) {
  /* the deepest pixel decides whether the arrays were large enough */
  size_t n = (size_t)l->width * (size_t)l->height;
  GLuint *counts = malloc(n * sizeof(GLuint)), most = 0;
  long past = 0, deepest = 0; /* fragments past the slots; pixels past 64 */
  *fragments = 0;
  *overflow = 0;
  int box[4] = {0, 0, l->width, l->height}; /* x0, y0, x1, y1 */
  int read = counts != NULL;
  if (counts) {
    glBindTexture(GL_TEXTURE_2D, l->counts);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, counts);
    box[0] = l->width, box[1] = l->height, box[2] = box[3] = 0;
    for (size_t i = 0; i < n; i++) {
      most = counts[i] > most ? counts[i] : most;
      *fragments += counts[i] < (GLuint)l->slots ? counts[i] : (GLuint)l->slots;
      if (counts[i] <= (GLuint)l->slots)
        continue;
      past += (long)(counts[i] - (GLuint)l->slots);
      deepest += counts[i] > SATF_MAX_FRAGMENTS;
      ++*overflow;
      int x = (int)(i % (size_t)l->width), y = (int)(i / (size_t)l->width);
      box[0] = x < box[0] ? x : box[0], box[1] = y < box[1] ? y : box[1];
      box[2] = x + 1 > box[2] ? x + 1 : box[2];
      box[3] = y + 1 > box[3] ? y + 1 : box[3];
    }
    /* Arrays deep enough for the deepest pixel cost every pixel of the
     * frame as many slots (the shared ponytail's 100 fragments in a few
     * of its pixels: 64 slots, 315 MB at 640x480); the pool takes the
     * fragments past them in any pixel. Half of it left free for a
     * camera that moves on. */
    if (!nearest) {
      l->pool_slots = lists_slots_within(counts, n, (long)l->pool / 2);
      l->deepest_pixels = deepest;
    }
    free(counts);
  }
  if (!nearest) /* the pool held them, or the nearest passes keep slots */
    *fragments += past <= (long)l->pool ? past : 0;
  /* its fragments past the slots went there (counts unread: maybe) */
  if (!nearest && (*overflow > 0 || !read))
    l->pool_dirty = 1;
  if (!nearest) { /* the counts are the plain pass's in both */
    l->overflow_box[0] = box[0], l->overflow_box[1] = box[1];
    l->overflow_box[2] = box[2] > box[0] ? box[2] - box[0] : 0;
    l->overflow_box[3] = box[3] > box[1] ? box[3] - box[1] : 0;
  }
  return most;
}
