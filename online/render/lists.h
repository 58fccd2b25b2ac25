/* lists.h - per-pixel fragment arrays (private to online/render): an
 * r32ui counter per pixel and a layered rgba32ui image of `slots`
 * fragments (colour as halves, depth), the pool of the fragments past a
 * pixel's slots (a storage buffer, one entry per pixel of room, chained
 * per pixel from an r32ui head), the depth keys of the nearest passes
 * (drawn where the pool is full), and the framebuffer the hair's fragment
 * passes draw into (it tests against the frame's depth). The slots a
 * texture rather than a storage buffer: llvmpipe caps buffers at 128 MB,
 * and a per-pixel counter avoids the contention of one global atomic
 * counter, which made linked lists of every fragment three times slower
 * there (the pool takes only the few past the slots). lists.c owns them;
 * the shaders that fill and resolve them are glsl/list_write.glsl and
 * glsl/resolve_fs.glsl. */
#ifndef SATF_RENDER_LISTS_H
#define SATF_RENDER_LISTS_H

#include "satf/gl.h"
#include "satf/render.h"

/* Fragments each pixel can keep at first; the arrays grow (up to
 * SATF_MAX_FRAGMENTS) when a frame needs more. */
#define START_SLOTS 16

/* The most fragments the pool past the arrays holds (16 bytes each; a
 * frame takes one per pixel up to this many). */
#define LISTS_POOL_MAX (1 << 22)

typedef struct frag_lists {
  GLuint counts, frags;
  /* the plain pass's fragments past a pixel's slots (glsl/list_write.glsl):
   * a storage buffer of a count, a capacity and `pool` entries, and each
   * pixel's last entry (r32ui) */
  GLuint pool_buf, heads;
  int pool;
  int pool_dirty; /* written since cleared: lists_begin clears it */
  GLuint keys;    /* per-pixel depth keys of the nearest `slots` fragments,
                     made when a pixel first overflows (0: none yet) */
  GLuint fbo;
  GLuint depth; /* the frame's depth texture, which fbo tests against */
  /* the nearest passes' framebuffer and its depth, a mask of the pixels
   * the plain pass overflowed (lists_mask_overflow), and the program and
   * empty vertex array that draw it; made with the keys */
  GLuint mask_fbo, mask, mask_prog, mask_vao;
  int slots; /* fragments kept per pixel */
  /* the fewest slots (START_SLOTS .. SATF_MAX_FRAGMENTS) past which the
   * last plain pass's fragments fill at most half the pool: lists_count */
  int pool_slots;
  /* the pixels of the last plain pass deeper than SATF_MAX_FRAGMENTS */
  long deepest_pixels;
  int width, height;
  /* x, y, width, height of the pixels the last plain pass overflowed (the
   * nearest passes draw only there) */
  int overflow_box[4];
} frag_lists;

/* The framebuffer for width x height with `depth` (the frame's depth
 * texture) attached, and arrays of the slots they had (START_SLOTS at
 * first). */
satf_status lists_attach(frag_lists *l, int width, int height, GLuint depth,
                         satf_error *err);
/* Arrays of `slots` fragments per pixel (the keys dropped). */
satf_status lists_alloc(frag_lists *l, int slots, satf_error *err);
/* After a plain pass: the arrays grown to `slots` a pixel (at most
 * SATF_MAX_FRAGMENTS) when they hold fewer; *grown says whether they did,
 * and so whether the pass must be drawn again. The colour's composite asks
 * for pool_slots, the depth's for the deepest pixel's count and 4 more. */
satf_status lists_grow(frag_lists *l, int slots, int *grown, satf_error *err);
/* `slots` layers of depth keys and one more, the counter of the second
 * nearest pass's stores (glsl/list_write.glsl), and the overflow mask at
 * the arrays' size, unless they exist. */
satf_status lists_alloc_keys(frag_lists *l, satf_error *err);
void lists_release(frag_lists *l);
/* Binds the arrays as images for a fill pass of `mode` (u_list_mode:
 * 0 plain, which clears the counts; 1 and 2 the nearest passes, 1 clearing
 * the keys) and their framebuffer: the frame's depth for a plain pass,
 * the overflow mask for the nearest passes, which must draw with the
 * depth test on (LEQUAL, no writes) after lists_mask_overflow. */
void lists_bind(const frag_lists *l, int mode);
/* After a plain pass that overflowed: the nearest passes' depth, the
 * frame's where a pixel received more fragments than its slots and 0
 * elsewhere, so that their early depth test spares the shading of every
 * pixel the plain pass kept whole (the ponytail: its ~100 overflowing
 * pixels lie in a box of 150 x 170 at the tie). Leaves the depth test
 * off and depth writes on. */
void lists_mask_overflow(const frag_lists *l);
/* The fewest slots a pixel, START_SLOTS .. SATF_MAX_FRAGMENTS, past which
 * the n pixels' fragment counts leave at most `room` fragments
 * (SATF_MAX_FRAGMENTS where none does). */
int lists_slots_within(const GLuint *counts, size_t n, long room);
/* After a fill: the largest number of fragments a pixel received, the
 * fragments kept (*fragments: those in the slots, and those past them the
 * pool holds) and the pixels that received more than `slots` (*overflow);
 * a plain pass (nearest 0) also records their box and pool_slots. */
GLuint lists_count(frag_lists *l, int nearest, long *fragments, long *overflow);
/* Before a plain pass: the pool emptied, where a pass wrote to it since
 * (one that overflowed a pixel's slots). */
void lists_begin(frag_lists *l);
/* After a plain pass: whether the pool held every fragment past the slots
 * (then the resolve reads it, and no nearest pass is needed). */
int lists_pool_held(const frag_lists *l);

#endif
