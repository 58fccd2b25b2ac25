/* png_compare - test helper: compares two 8-bit PNGs of equal size.
 *
 * usage: png_compare A.png B.png MAXDIFF
 *
 * Exits 0 when every RGB channel differs by at most MAXDIFF (in 1/255
 * steps) and the pictures are not blank (some pixel of A differs from its
 * first pixel by more than 16 steps, so two empty frames do not pass);
 * 1 otherwise, printing the largest difference and where it is. */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static unsigned char *load(const char *path, png_uint_32 *w, png_uint_32 *h) {
  png_image img;
  memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path)) {
    fprintf(stderr, "png_compare: %s: %s\n", path, img.message);
    return NULL;
  }
  img.format = PNG_FORMAT_RGB;
  unsigned char *buf = malloc(PNG_IMAGE_SIZE(img));
  if (!buf || !png_image_finish_read(&img, NULL, buf, 0, NULL)) {
    fprintf(stderr, "png_compare: %s: %s\n", path,
            buf ? img.message : "out of memory");
    free(buf);
    png_image_free(&img);
    return NULL;
  }
  *w = img.width;
  *h = img.height;
  return buf;
}

int main(int argc, char **argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: png_compare A.png B.png MAXDIFF\n");
    return 2;
  }
  char *end;
  long tol = strtol(argv[3], &end, 10);
  if (*end || tol < 0 || tol > 255) {
    fprintf(stderr, "png_compare: MAXDIFF must be 0..255, got '%s'\n", argv[3]);
    return 2;
  }
  png_uint_32 wa, ha, wb, hb;
  unsigned char *a = load(argv[1], &wa, &ha), *b = load(argv[2], &wb, &hb);
  int rc = 1;
  if (!a || !b)
    goto done;
  if (wa != wb || ha != hb) {
    fprintf(stderr, "png_compare: sizes differ: %ux%u vs %ux%u\n", (unsigned)wa,
            (unsigned)ha, (unsigned)wb, (unsigned)hb);
    goto done;
  }
  size_t n = (size_t)wa * ha * 3, worst = 0;
  int most = 0, spread = 0;
  long over = 0;
  for (size_t i = 0; i < n; i++) {
    int d = abs((int)a[i] - (int)b[i]);
    if (d > most) {
      most = d;
      worst = i;
    }
    over += d > tol;
    int s = abs((int)a[i] - (int)a[i % 3]);
    spread = s > spread ? s : spread;
  }
  printf("png_compare: %ux%u, max difference %d/255 at pixel (%zu, %zu), %ld "
         "channels over %ld; largest step from the first pixel %d\n",
         (unsigned)wa, (unsigned)ha, most, worst / 3 % wa, worst / 3 / wa, over,
         tol, spread);
  rc = most <= tol && spread > 16 ? 0 : 1;
done:
  free(a);
  free(b);
  return rc;
}
