/* kdtree.h - a static k-d tree over 3-D points for the SATF look-up's
 * nearest-sample search. Built once; queries are read-only and thread-safe. */
#ifndef SATF_DB_KDTREE_H
#define SATF_DB_KDTREE_H

typedef struct satf_kdtree satf_kdtree;

/* points: n x 3 floats, copied. Returns NULL on allocation failure. */
satf_kdtree *satf_kdtree_build(const float *points, int n);
void satf_kdtree_destroy(satf_kdtree *tree);

/* The k nearest points to q, nearest first (ties broken by lower index).
 * Returns the number found (min(k, n)). */
int satf_kdtree_nearest(const satf_kdtree *tree, const float q[3], int k,
                        int *index, float *dist2);

#endif
