/* capture.h - collects what a call prints to stderr, so tests can check
 * the exact wording of command-line messages. */
#ifndef SATF_TESTS_COMMON_CAPTURE_H
#define SATF_TESTS_COMMON_CAPTURE_H

#include <stdio.h>
#include <string.h>
#include <unistd.h>

typedef struct capture {
  int saved_fd;
  FILE *file;
  char text[1024];
} capture;

/* Sends stderr to a temporary file until capture_end. */
static inline void capture_begin(capture *c) {
  fflush(stderr);
  c->file = tmpfile();
  c->saved_fd = dup(fileno(stderr));
  dup2(fileno(c->file), fileno(stderr));
}

/* Restores stderr and returns what was printed (at most 1023 bytes). */
static inline const char *capture_end(capture *c) {
  fflush(stderr);
  dup2(c->saved_fd, fileno(stderr));
  close(c->saved_fd);
  rewind(c->file);
  size_t n = fread(c->text, 1, sizeof c->text - 1, c->file);
  c->text[n] = '\0';
  fclose(c->file);
  return c->text;
}

#endif
