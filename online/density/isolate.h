/* isolate.h - runs a reader over an untrusted file in a child process, so
 * that a crash or hang inside a third-party parser (OpenVDB) becomes a clear
 * error naming the file instead of taking the caller down. Private to
 * online/density/. */
#ifndef SATF_DENSITY_ISOLATE_H
#define SATF_DENSITY_ISOLATE_H

#include "satf/common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Runs in the child: reads the untrusted file and sends what the parent
 * needs with satf_isolated_send on fd. */
typedef satf_status (*satf_isolated_fn)(void *ctx, int fd, satf_error *err);

/* Runs in the parent for each record the child sent, in order. It must treat
 * the payload as untrusted too (a damaged file can make a parser emit
 * anything short of a crash) and validate every field. */
typedef satf_status (*satf_isolated_recv_fn)(void *ctx, int tag,
                                             const void *data, size_t size,
                                             satf_error *err);

/* Largest payload of one record. */
#define SATF_ISOLATED_MAX_RECORD 8192

/* Sends one record (tag > 0) from the child; 0 on success. */
int satf_isolated_send(int fd, int tag, const void *data, size_t size);

/* Forks a child that runs child(child_ctx, fd, err) under a time limit of
 * `seconds` and hands each record it sends to recv(recv_ctx, ...), so the
 * caller never parses the file itself. Returns SATF_OK when the child
 * finished with SATF_OK and recv accepted every record; the child's or
 * recv's status and message when one of them failed; SATF_ERR_CORRUPT with
 * "PATH: damaged KIND: the reader crashed (SIGSEGV)" (or the signal or exit
 * status it died of, or the time limit it ran past) when the child did not
 * finish (a child that ran out of time before its first record is started
 * once more, see isolate.c); SATF_ERR_IO when no child could be started. child
 * must only run code that is safe after fork() in a process that may have other
 * threads (see isolate.c). */
satf_status satf_isolated_run(satf_isolated_fn child, void *child_ctx,
                              satf_isolated_recv_fn recv, void *recv_ctx,
                              const char *path, const char *kind,
                              unsigned seconds, satf_error *err);

#ifdef __cplusplus
}
#endif

#endif
