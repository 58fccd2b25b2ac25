/* list_write.glsl - one fragment into the per-pixel fragment arrays that
 * resolve_fs.glsl sorts and composites (SATF eq. 14 over everything the
 * pixel sees): a cluster's composite along the pixel's ray
 * (shade_fs.glsl) or a sparse cluster's strand (strand_fs.glsl with LIST,
 * sparse.c), so the two kinds of hair are ordered by depth together. */
/* The depth test against the opaque meshes must run before the shader:
 * a fragment's image stores happen whatever a later test decides, so hair
 * behind a head would otherwise be composited over it. */
layout(early_fragment_tests) in;
uniform int u_slots;
/* 0: every fragment takes the next slot; 1: only the depth keys of the
 * u_slots nearest are kept (u_keys); 2: fragments no farther than the
 * u_slots-th nearest take slots (cluster_gpu.c, cluster_gpu_lists). Modes 1 and 2
 * follow mode 0 of the same frame and redo only the pixels it overflowed
 * (its count, which they leave, over u_slots): the others keep what it
 * stored, which was every fragment they received. */
uniform int u_list_mode;
layout(binding = 0, r32ui) uniform coherent uimage2D u_counts;
layout(binding = 1, rgba32ui) uniform writeonly uimage2DArray u_frags;
/* u_slots layers of keys, then mode 2's count of stores (cleared with the
 * keys to 0xFFFFFFFF, so its first add returns slot 0 - 1) */
layout(binding = 2, r32ui) uniform coherent uimage2DArray u_keys;
/* The plain pass's fragments past a pixel's u_slots: a pool shared by the
 * frame (lists.h), each entry the fragment as the arrays hold it with the
 * pool index + 1 of the pixel's previous one in w (0: none), the pixel's
 * last in u_heads; resolve_fs.glsl keeps the nearest u_slots of the array
 * and the pool, so the nearest passes are drawn only when the pool is
 * full. */
layout(binding = 3, r32ui) uniform coherent uimage2D u_heads;
layout(std430, binding = 7) buffer satf_pool {
  uint g_pool_count, g_pool_capacity, g_pool_pad0, g_pool_pad1;
  uvec4 g_pool[];
};
/* whether the nearest passes need nothing of this fragment: mode 0 did not
 * overflow its pixel (they draw only inside the box of those that
 * overflowed, cluster_gpu_lists, and their early depth test against the
 * overflow mask, lists_mask_overflow, turns the others away before the
 * shading but at the near plane; asked in those modes only, so that mode
 * 0 pays nothing for it) */
bool list_skip() {
  return imageLoad(u_counts, ivec2(gl_FragCoord.xy)).r <= uint(u_slots);
}
/* col premultiplied by alpha */
void list_write(vec3 col, float alpha) {
  ivec2 px = ivec2(gl_FragCoord.xy);
  /* depth >= 0, so its bits order as the depths do */
  uint key = floatBitsToUint(gl_FragCoord.z);
  if (u_list_mode == 1) {
    if (list_skip()) return;
    /* lock-free sorted insertion: each atomicMin keeps the smaller key in
     * slot i and carries the larger on, so slot i ends as the (i+1)-th
     * smallest key whatever the arrival order */
    for (int i = 0; i < u_slots && key != 0xFFFFFFFFu; i++)
      key = max(key, imageAtomicMin(u_keys, ivec3(px, i), key));
    return;
  }
  uint slot;
  if (u_list_mode == 2) {
    if (list_skip() || key > imageLoad(u_keys, ivec3(px, u_slots - 1)).r)
      return;
    slot = imageAtomicAdd(u_keys, ivec3(px, u_slots), 1u) + 1u;
  } else {
    slot = imageAtomicAdd(u_counts, px, 1u);
  }
  if (slot < uint(u_slots)) {
    imageStore(u_frags, ivec3(px, int(slot)),
               uvec4(packHalf2x16(col.rg), packHalf2x16(vec2(col.b, alpha)),
                     floatBitsToUint(gl_FragCoord.z), 0u));
    return;
  }
  if (u_list_mode != 0) return;
  uint i = atomicAdd(g_pool_count, 1u);
  if (i >= g_pool_capacity) return;
  g_pool[i] = uvec4(packHalf2x16(col.rg), packHalf2x16(vec2(col.b, alpha)),
                    floatBitsToUint(gl_FragCoord.z),
                    imageAtomicExchange(u_heads, px, i + 1u));
}
