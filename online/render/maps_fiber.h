/* maps_fiber.h - the maps of the physical shading mode: every
 * HSV's radiance from a fibre database's per-lobe records (satf/db.h,
 * format version 2) times the longitudinal M_p of the fibre model (d'Eon
 * 2011 eq. 7, satf/fiber.h) at the HSV's view and light angles, for every
 * light of the scene, in the hair's colour.
 *
 * Texture layout. As maps.h, but a texel holds two quads of halfs, 8 in
 * all (a GL_RGBA32UI texel, so the shading pass reads both in one fetch):
 * the key quad, (R, G, B) of the key light's radiance per unit coverage
 * and alpha, then the fill quad, the other lights' radiance summed and
 * the s-map sum of eq. 12 (the key light alone is shadowed by the deep
 * opacity map and the s-map, as in the paper's mode). HSV i's rows 2i and
 * 2i + 1 hold the records of its boundary sectors i and i + 1 (SATF
 * eq. 7).
 *
 * Choices (docs/shading.md): the records are traced with the light
 * in the fibres' normal plane, so absorption is taken at normal incidence
 * (a grazing view's longer internal path, 1 / cos(theta_t) <= 1.3 times,
 * is not added); a whole database is re-levelled at the hair's RGB
 * absorption once, when the renderer is made, so a look-up interpolates
 * no absorption. */
#ifndef SATF_ONLINE_MAPS_FIBER_H
#define SATF_ONLINE_MAPS_FIBER_H

#include "maps.h"
#include "satf/scene.h"
#include "view.h"

typedef struct satf_maps_fiber satf_maps_fiber;

/* A light in the prototype's frame (xyz, w = 0: direction towards it, 1:
 * position) and its irradiance (colour times intensity; a point light's
 * at unit distance). */
typedef struct satf_fiber_light {
  float local[4];
  float rgb[3];
} satf_fiber_light;

/* The lights of view v in the frame whose inverse transform is inv, with
 * their irradiance, the key light first (v->nlights of them). */
void maps_fiber_lights(const view *v, const float inv[16],
                       satf_fiber_light *lights);

/* Fails with SATF_ERR_INCOMPATIBLE for a Phong database. */
satf_status satf_maps_fiber_create(const satf_db *db,
                                   const satf_scene_material *material,
                                   int threads, satf_maps_fiber **out,
                                   satf_error *err);
void satf_maps_fiber_destroy(satf_maps_fiber *fiber);

/* Writes every layer of a cluster's maps (layers slices of
 * satf_maps_layer_texels * 8 halfs, the s-map sums of eq. 12 in the
 * eighth half of a texel) as half floats (half.h); lights[0] is the
 * key light. trt 0 leaves out the TRT lobe, the physical secondary
 * highlight (the Fig. 4b switch in this mode). Only part `part` of
 * `parts` (0 <= part < parts) is written: that share of the su columns of
 * HSVs, so that threads may build one cluster's parts at once. sums:
 * scratch of satf_maps_fiber_scratch_floats. Returns the look-ups made. */
int satf_maps_fiber_build(const satf_maps *maps, const satf_maps_fiber *fiber,
                          const satf_shell_geom *g, const float eye[3],
                          const satf_fiber_light *lights, int n_lights, int trt,
                          const satf_map_options *opt, int part, int parts,
                          float *sums, uint16_t *texels);
size_t satf_maps_fiber_scratch_floats(const satf_shell_geom *g, int width);

/* What satf_maps_fiber_build reads, for the GPU's copy (maps_gpu.h): the
 * re-levelled database, M_p's table (mp_size^2 nodes, node (a, b) at
 * sin theta_i = -1 + 2 a / (mp_size - 1), sin theta_o likewise in b, the
 * four lobes R, TT, TRT, MS side by side), the orientation-free levels
 * (per sample and rel_bins relative azimuth bins, rel_stride floats:
 * alpha, then the lobe channels from SATF_DB_CH_R on), the absorption
 * levels and each colour's. */
typedef struct maps_fiber_tables {
  const satf_db *db;
  const float *mp;
  int mp_size;
  const float *rel;
  int rel_bins, rel_stride;
  int levels, level_of[3];
} maps_fiber_tables;
void maps_fiber_tables_get(const satf_maps_fiber *fiber, maps_fiber_tables *t);

/* The sizes of what satf_maps_fiber_create makes of database db for
 * material mat, known before it is made (the memory estimate, budget.c):
 * the hair's absorption levels, the re-levelled database's channels,
 * M_p's table side, the orientation-free levels' bins and floats a bin. */
typedef struct maps_fiber_shape {
  int levels, channels, mp_size, rel_bins, rel_stride;
} maps_fiber_shape;
void maps_fiber_shape_of(const satf_db *db, const satf_scene_material *mat,
                         maps_fiber_shape *out);

/* Fibre tangents around a tilted sector's cone, the curl's model
 * (satf_map_options.tilt). 32 changed the generated curls' frame
 * (--quality draft, 640x480) by SSIM 0.992 (SSIM4 0.994, luminance 0.2%)
 * and its SSIM4 against Cycles not at all (0.410), for four times the M_p
 * look-ups (8 cost those curls' maps C 30-39 -> 50-54 ms a frame, the
 * tangents found once a sector: cone_at). */
#define TILT_TANGENTS 8

/* The TILT_TANGENTS unit tangents at angle `tilt` about the unit `hair`,
 * at azimuths 2 pi (k + 1/2) / TILT_TANGENTS from the sector's normal N
 * (frame + 3, satf_shell_geom's 9 floats) towards the direction across
 * the hair within the sector's surface: the phase direction T (frame + 6)
 * for the hair N x T, hair x N for a hair the strands turned (`own`,
 * satf_shell_geom_set_hair), across which T no longer lies. */
void maps_cone_tangents(const float hair[3], const float *frame, int own,
                        float tilt, float tangent[TILT_TANGENTS][3]);

#endif
