/* isolate.c - see isolate.h.
 *
 * Why fork() and not posix_spawn() of a helper program: a helper would have
 * to be found at run time next to every program and test that links
 * satf_density, and a stale or missing helper would silently disable the
 * check. fork() needs nothing on disk, but in a process that may already
 * have threads the child is a copy of only the calling thread, and any lock
 * another thread held at that instant stays locked forever in the child.
 * What the child runs is therefore restricted (see satf_vdb_read): OpenVDB
 * is initialised in the parent before the first fork, the child only reads
 * and walks one grid serially (no TBB algorithm, whose workers do not exist
 * in the child; OpenVDB decompresses blosc with one thread), and glibc's
 * malloc and stdio locks are reset by glibc's own fork handlers. The one
 * remaining hazard, another thread of the caller holding a lock the child
 * needs at the instant of the fork (OpenVDB's registry, a driver's lock
 * taken by llvmpipe's threads in a renderer), cannot corrupt anything: the
 * child blocks and runs into its time limit. Such a child has sent nothing,
 * which a parser hanging on a damaged file may also do, so a child that ran
 * out of time before its first record is started once more, from a fresh
 * fork; a file that hangs the parser twice is reported as damaged.
 *
 * Why the child sends records instead of a verdict: a damaged file can
 * corrupt the heap without crashing (glibc notices only some overflows), so
 * a child that survived proves nothing about the same parse in the parent.
 * The parent therefore never parses the file; it receives fixed-layout
 * records, checks every field and builds its own copy. */
#define _GNU_SOURCE /* pipe2 */

#include "isolate.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *signal_name(int sig) {
  switch (sig) {
  case SIGSEGV: return "SIGSEGV";
  case SIGBUS: return "SIGBUS";
  case SIGFPE: return "SIGFPE";
  case SIGILL: return "SIGILL";
  case SIGABRT: return "SIGABRT";
  case SIGTRAP: return "SIGTRAP";
  case SIGSYS: return "SIGSYS";
  case SIGKILL: return "SIGKILL";
  default: return NULL;
  }
}

static int write_all(int fd, const void *buf, size_t n) {
  const char *p = buf;
  while (n > 0) {
    const ssize_t w = write(fd, p, n);
    if (w < 0 && errno == EINTR)
      continue;
    if (w <= 0)
      return -1;
    p += w;
    n -= (size_t)w;
  }
  return 0;
}

/* The parent's input buffer over the pipe. */
typedef struct reader {
  int fd;
  size_t pos, len;
  unsigned char buf[1 << 16];
} reader;

/* Bytes read before end of file or an error. */
static size_t read_all(reader *r, void *dst, size_t n) {
  unsigned char *p = dst;
  size_t got = 0;
  while (got < n) {
    if (r->pos == r->len) {
      const ssize_t k = read(r->fd, r->buf, sizeof r->buf);
      if (k < 0 && errno == EINTR)
        continue;
      if (k <= 0)
        break;
      r->pos = 0;
      r->len = (size_t)k;
    }
    size_t take = r->len - r->pos;
    if (take > n - got)
      take = n - got;
    memcpy(p + got, r->buf + r->pos, take);
    r->pos += take;
    got += take;
  }
  return got;
}

/* Record framing: a header, then `size` bytes; tag 0 ends the stream and
 * carries the child's satf_error. */
typedef struct record_header {
  uint32_t tag, size;
} record_header;

/* The child's output buffer: records are small and a system call each
 * would dominate the transfer. Only the single-threaded child uses it. */
static unsigned char send_buf[1 << 16];
static size_t send_len;

static int send_flush(int fd) {
  const int r = write_all(fd, send_buf, send_len);
  send_len = 0;
  return r;
}

static int send_bytes(int fd, const void *data, size_t size) {
  if (send_len + size > sizeof send_buf && send_flush(fd) != 0)
    return -1;
  memcpy(send_buf + send_len, data, size);
  send_len += size;
  return 0;
}

int satf_isolated_send(int fd, int tag, const void *data, size_t size) {
  if (size > SATF_ISOLATED_MAX_RECORD)
    return -1;
  const record_header h = {(uint32_t)tag, (uint32_t)size};
  return send_bytes(fd, &h, sizeof h) == 0 && send_bytes(fd, data, size) == 0
             ? 0
             : -1;
}

/* Provided by the sanitizer runtimes only. libFuzzer registers a death
 * callback that saves the current input as a crash of the fuzz target; a
 * sanitizer error inside the child is the parser's, reported by the parent. */
void __sanitizer_set_death_callback(void (*callback)(void))
    __attribute__((weak));

static _Noreturn void child_main(int fd, satf_isolated_fn fn, void *ctx,
                                 unsigned seconds) {
  if (__sanitizer_set_death_callback)
    __sanitizer_set_death_callback(NULL);
  /* Default actions for the fatal signals: a handler inherited from the
   * caller (a sanitizer's, or libFuzzer's, which would save the input as a
   * crash of the fuzz target) must not take the parser's crash for its own,
   * and SIGALRM must end the child whatever the caller did with it. */
  static const int fatal[] = {SIGSEGV, SIGBUS,  SIGFPE, SIGILL,
                              SIGABRT, SIGTRAP, SIGSYS, SIGALRM};
  sigset_t unblock;
  sigemptyset(&unblock);
  for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; ++i) {
    signal(fatal[i], SIG_DFL);
    sigaddset(&unblock, fatal[i]);
  }
  sigprocmask(SIG_UNBLOCK, &unblock, NULL);
  /* A parent that stopped listening ends the child at its next write. */
  signal(SIGPIPE, SIG_DFL);
  /* A crash here is expected and reported; a core file would only litter. */
  const struct rlimit no_core = {0, 0};
  setrlimit(RLIMIT_CORE, &no_core);
  alarm(seconds);
  satf_error e;
  satf_error_clear(&e);
  e.status = fn(ctx, fd, &e);
  const record_header h = {0, (uint32_t)sizeof e};
  const int sent = send_bytes(fd, &h, sizeof h) == 0 &&
                   send_bytes(fd, &e, sizeof e) == 0 && send_flush(fd) == 0;
  /* _exit, not exit: the caller's atexit handlers and stdio buffers belong
   * to the parent. */
  _exit(sent ? 0 : 1);
}

/* The error for a child that did not hand back a result. */
static satf_status child_failed(int wstatus, const char *path, const char *kind,
                                unsigned seconds, satf_error *err) {
  if (WIFSIGNALED(wstatus)) {
    const int sig = WTERMSIG(wstatus);
    if (sig == SIGALRM)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: damaged %s: the reader did not finish within "
                            "%u s",
                            path, kind, seconds);
    if (sig == SIGKILL)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: damaged %s: the reader was killed (SIGKILL), "
                            "most likely for running out of memory",
                            path, kind);
    const char *name = signal_name(sig);
    if (name)
      return satf_error_set(err, SATF_ERR_CORRUPT,
                            "%s: damaged %s: the reader crashed (%s)", path,
                            kind, name);
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: damaged %s: the reader crashed (signal %d)",
                          path, kind, sig);
  }
  if (WIFEXITED(wstatus) && WEXITSTATUS(wstatus) != 0)
    return satf_error_set(err, SATF_ERR_CORRUPT,
                          "%s: damaged %s: the reader crashed (exit status %d)",
                          path, kind, WEXITSTATUS(wstatus));
  return satf_error_set(err, SATF_ERR_CORRUPT,
                        "%s: damaged %s: the reader stopped without a result",
                        path, kind);
}

/* Reads records from the child until its end record, end of file or a
 * record recv refuses. Returns 1 with the child's result in *end when the
 * end record arrived, 0 when the stream stopped short, -1 when recv (or the
 * framing) failed, with err set. */
static int receive(reader *in, satf_isolated_recv_fn recv, void *ctx,
                   const char *path, const char *kind, satf_error *end,
                   size_t *records, satf_error *err) {
  unsigned char buf[SATF_ISOLATED_MAX_RECORD];
  for (;; ++*records) {
    record_header h;
    if (read_all(in, &h, sizeof h) != sizeof h)
      return 0;
    if (h.tag == 0)
      return h.size == sizeof *end && read_all(in, end, sizeof *end) == h.size;
    if (h.size > sizeof buf) {
      satf_error_set(err, SATF_ERR_INTERNAL,
                     "%s: the %s reader sent a record of %u bytes", path, kind,
                     h.size);
      return -1;
    }
    if (read_all(in, buf, h.size) != h.size)
      return 0;
    if (recv(ctx, (int)h.tag, buf, h.size, err) != SATF_OK)
      return -1;
  }
}

/* One child from fork to verdict; *stalled tells whether it ran out of
 * time before sending a record. */
static satf_status run_child(satf_isolated_fn child, void *child_ctx,
                             satf_isolated_recv_fn recv, void *recv_ctx,
                             const char *path, const char *kind,
                             unsigned seconds, int *stalled, satf_error *err) {
  *stalled = 0;
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    return satf_error_set(err, SATF_ERR_IO,
                          "%s: cannot read the %s in a child process: %s", path,
                          kind, strerror(errno));
  const pid_t pid = fork();
  if (pid < 0) {
    const int e = errno;
    close(fds[0]);
    close(fds[1]);
    return satf_error_set(err, SATF_ERR_IO,
                          "%s: cannot read the %s in a child process: %s", path,
                          kind, strerror(e));
  }
  if (pid == 0) {
    close(fds[0]);
    child_main(fds[1], child, child_ctx, seconds);
  }
  close(fds[1]);
  satf_error end;
  satf_error recv_err;
  satf_error_clear(&recv_err);
  /* Stops at the end record, or at end of file when the child died (at the
   * latest when its alarm fires). */
  reader *in = malloc(sizeof *in);
  int got = -1;
  size_t records = 0;
  if (in) {
    in->fd = fds[0];
    in->pos = in->len = 0;
    got = receive(in, recv, recv_ctx, path, kind, &end, &records, &recv_err);
    free(in);
  } else {
    satf_error_set(&recv_err, SATF_ERR_NOMEM, "%s: out of memory", path);
  }
  close(fds[0]);
  if (got < 0)
    kill(pid, SIGKILL); /* its output was refused; no need to wait for it */
  int wstatus = 0;
  pid_t w;
  while ((w = waitpid(pid, &wstatus, 0)) < 0 && errno == EINTR) {
  }
  if (got < 0)
    return satf_error_set(err, recv_err.status, "%s", recv_err.message);
  /* ECHILD: the caller ignores SIGCHLD, so the child was reaped unseen; its
   * end record says it finished. */
  const int exited = w == pid ? WIFEXITED(wstatus) && !WEXITSTATUS(wstatus)
                              : w < 0 && errno == ECHILD;
  if (!got || !exited) {
    *stalled = records == 0 && w == pid && WIFSIGNALED(wstatus) &&
               WTERMSIG(wstatus) == SIGALRM;
    return child_failed(exited ? 0 : wstatus, path, kind, seconds, err);
  }
  end.message[sizeof end.message - 1] = '\0';
  if (end.status == SATF_OK)
    return SATF_OK;
  return satf_error_set(err, end.status, "%s", end.message);
}

satf_status satf_isolated_run(satf_isolated_fn child, void *child_ctx,
                              satf_isolated_recv_fn recv, void *recv_ctx,
                              const char *path, const char *kind,
                              unsigned seconds, satf_error *err) {
  int stalled = 0;
  const satf_status st = run_child(child, child_ctx, recv, recv_ctx, path, kind,
                                   seconds, &stalled, err);
  if (!stalled)
    return st;
  /* Nothing was received, so recv's context is as the caller gave it. */
  return run_child(child, child_ctx, recv, recv_ctx, path, kind, seconds,
                   &stalled, err);
}
