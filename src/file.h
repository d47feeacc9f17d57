/* Whole files in and out, for the mesh calls (io.c) and the scene calls (scene.c, scene_save.c): reading a file
 * into memory in one piece, and writing one atomically (a temporary file beside the target, renamed over it only
 * once complete, so that a failed or interrupted save leaves the previous file as it was). Not installed. */
#ifndef RESURF_FILE_H
#define RESURF_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "internal.h"

/* Reads the whole file at path into a new buffer from alloc, with a NUL after the last byte (not counted in
 * *out_size). Folders, devices and sockets are refused before they are opened (opening a device can have effects
 * of its own). A regular file is read at its size (one read), up to max_bytes (0: no limit but the machine's); a
 * pipe up to max_bytes and 64 MiB + 1 KiB per triangle of max_triangles (0: no limit), so that an endless writer
 * cannot eat all memory. progress (NULL: none) may cancel a read that a signal interrupted. Errors name path. */
resurf_status resurfi_read_file(const resurf_allocator *alloc, const char *path, uint64_t max_bytes,
                                size_t max_triangles, const resurf_progress *progress, char **out_data,
                                size_t *out_size, resurf_error *error);

/* Creates the temporary file for path, "<dir>/.<name>.tmp-XXXXXX", with O_EXCL (so that the umask applies as for
 * any new file; mkstemp would force 0600) and the permissions of the file at path when there is one. *out_tmp
 * receives its name (from alloc), *out_fd its descriptor. */
resurf_status resurfi_temp_create(const resurf_allocator *alloc, const char *path, char **out_tmp, int *out_fd,
                                  resurf_error *error);
/* Renames the complete (closed) temporary file tmp over path; removes it when that fails. Frees tmp. */
resurf_status resurfi_temp_commit(const resurf_allocator *alloc, char *tmp, const char *path, resurf_error *error);
/* Removes the temporary file tmp and frees its name (NULL: nothing to do). */
void resurfi_temp_discard(const resurf_allocator *alloc, char *tmp);

/* Writes size bytes to path atomically: a temporary file beside it (resurfi_temp_create), renamed over path once
 * complete; on failure no new file and no partial file is left. A path that names a folder (ending in /) is
 * RESURF_ERR_INVALID_ARGUMENT. Errors name path. */
resurf_status resurfi_save_file(const resurf_allocator *alloc, const char *path, const void *data, size_t size,
                                resurf_error *error);

/* Writes size bytes to fd, again after a signal interrupts; returns 0, or the errno of the failure (EIO when the
 * system accepts nothing). */
int resurfi_write_all(int fd, const void *data, size_t size);

#endif
