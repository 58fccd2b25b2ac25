/* tracks.h - a cluster's density from its own strands (scene density type
 * "tracks"): each strand's place in the normalised cross-section at evenly
 * spaced t, interpolated between slices, with the strand present only from
 * its root slice to its tip slice, so a cluster's density falls where its
 * strands end instead of stopping at t = 1 (satf_strands in density.c
 * forwards to these for that type). Not installed. */
#ifndef SATF_ONLINE_DENSITY_TRACKS_H
#define SATF_ONLINE_DENSITY_TRACKS_H

#include "satf/satf.h"
#include "satf/scene.h"

typedef struct density_tracks density_tracks;

satf_status density_tracks_create(const satf_scene_density *d,
                                  density_tracks **out, satf_error *err);
void density_tracks_destroy(density_tracks *t);
int density_tracks_count(const density_tracks *t);
/* Strand i at t, interpolated between its slices (held at its first and
 * last slice outside them). */
void density_tracks_position(const density_tracks *t, int i, float t_along,
                             float xy[2]);
/* SATF sec. 3.3: one circular Gaussian of peak 1/2 per strand present at
 * t, times d->scale; a strand that ends (or starts) inside a slice
 * interval is weighted by the fraction of the interval it covers there. */
float density_tracks_density(const density_tracks *t, float t_along, float x,
                             float y);

#endif
