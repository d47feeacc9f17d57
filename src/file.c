/* Whole files in and out (file.h): the one reader of whole files and the one atomic writer, shared by the mesh
 * calls (io.c) and the scene calls (scene.c, scene_save.c). */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "file.h"
#include "hash.h"

#ifndef O_CLOEXEC
#define O_CLOEXEC 0
#endif

/* ---- reading ------------------------------------------------------------------------------------------------- */

/* Bytes a stream (a pipe, or a file whose size the system does not know) may deliver before the load gives up:
 * 64 MiB plus 1 KiB per allowed triangle, far more than any format spends on a triangle (a text OBJ with normals
 * and texture coordinates needs about 150 bytes), so that an endless writer cannot eat all memory. */
static size_t stream_limit(size_t max_triangles)
{
    const size_t base = (size_t)64 << 20, per_triangle = 1024;
    if (max_triangles == 0 || max_triangles > (SIZE_MAX / 2 - base) / per_triangle)
        return SIZE_MAX / 2;
    return base + per_triangle * max_triangles;
}

resurf_status resurfi_read_file(const resurf_allocator *alloc, const char *path, uint64_t max_bytes,
                                size_t max_triangles, const resurf_progress *progress, char **out_data,
                                size_t *out_size, resurf_error *error)
{
    /* Look before opening: opening a device can have effects of its own (a tape rewinds, a tty becomes ours). */
    struct stat st;
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a directory, not a mesh file");
        if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode))
            return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a device or socket, not a mesh file");
    }
    /* O_NONBLOCK: opening a FIFO that no process writes to would wait for a writer forever. Reads block again
     * below, and a FIFO without a writer reads as the end of the file. */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot open: %s", strerror(errno));
    int fl = fcntl(fd, F_GETFL);
    if (fstat(fd, &st) != 0 || fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        int e = errno;
        close(fd);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot read: %s", strerror(e));
    }
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a directory, not a mesh file");
    }
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "is a device or socket, not a mesh file");
    }
    if (S_ISREG(st.st_mode) && (uint64_t)st.st_size >= SIZE_MAX / 2) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_LIMIT, path, 0, -1, "the file is too large for this machine");
    }
    if (max_bytes && (uint64_t)st.st_size > max_bytes) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_LIMIT, path, 0, -1, "the file is larger than %llu bytes",
                            (unsigned long long)max_bytes);
    }
    /* A regular file's size is known: the buffer it needs is justified by the file. Pipes (and files that report
     * size 0, such as those of /proc) grow the buffer as data comes, up to a limit. Either way the buffer keeps a
     * byte free for the NUL. */
    const bool sized = S_ISREG(st.st_mode) && st.st_size > 0;
    size_t limit = sized ? SIZE_MAX / 2 : stream_limit(max_triangles);
    const bool caller_limit = max_bytes && max_bytes < limit;
    if (caller_limit)
        limit = (size_t)max_bytes + 1; /* room for the NUL after max_bytes bytes */
    size_t cap = sized ? (size_t)st.st_size + 1 : 1 << 16, size = 0;
    char *data = resurfi_alloc(alloc, cap, 1);
    if (!data) {
        close(fd);
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory reading %zu bytes", cap);
    }
    resurf_status status = RESURF_OK;
    for (;;) {
        if (size == cap) {
            if (size >= limit) {
                if (caller_limit)
                    status = resurfi_fail(error, RESURF_ERR_LIMIT, path, 0, -1, "the file is larger than %llu bytes",
                                          (unsigned long long)max_bytes);
                else
                    status = resurfi_fail(error, RESURF_ERR_LIMIT, path, 0, -1,
                                          "the stream goes on past %zu bytes, more than the max_triangles limit "
                                          "(%zu triangles) can need",
                                          limit, max_triangles);
                break;
            }
            size_t grown = cap < limit / 2 ? cap * 2 : limit;
            char *bigger = resurfi_realloc(alloc, data, grown, 1);
            if (!bigger) {
                status = resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory reading the file");
                break;
            }
            data = bigger;
            cap = grown;
        }
        ssize_t n = read(fd, data + size, cap - size);
        if (n < 0 && errno == EINTR) {
            /* A signal interrupted a read that waits on a pipe: the caller may want to stop. */
            if (resurfi_progress(progress, RESURF_STAGE_LOAD, 0.0)) {
                status = resurfi_fail(error, RESURF_ERR_CANCELLED, path, 0, -1, "cancelled by the progress callback");
                break;
            }
            continue;
        }
        if (n < 0) {
            status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot read: %s", strerror(errno));
            break;
        }
        if (n == 0)
            break;
        size += (size_t)n;
    }
    close(fd);
    if (status != RESURF_OK) {
        resurfi_free(alloc, data);
        return status;
    }
    data[size] = 0; /* the last read found the end with room to spare */
    *out_data = data;
    *out_size = size;
    return RESURF_OK;
}

/* ---- writing ------------------------------------------------------------------------------------------------- */

int resurfi_write_all(int fd, const void *data, size_t size)
{
    const char *p = data;
    size_t done = 0;
    while (done < size) {
        ssize_t n = write(fd, p + done, size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            return errno ? errno : EIO;
        if (n == 0)
            return EIO;
        done += (size_t)n;
    }
    return 0;
}

/* Creates "<dir>/.<name>.tmp-XXXXXX" (tmp receives the name) and returns its descriptor, or -1 with errno set. */
static int create_temp(const char *path, char *tmp, size_t tmp_size)
{
    const char *slash = strrchr(path, '/');
    int dir_len = slash ? (int)(slash - path) + 1 : 0; /* keeps the slash; "/x" stays in "/" */
    const char *name = slash ? slash + 1 : path;
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    uint64_t seed = resurfi_mix64((uint64_t)now.tv_nsec ^ (uint64_t)now.tv_sec << 32 ^ (uint64_t)getpid() ^
                                  (uint64_t)(uintptr_t)tmp);
    static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    for (uint64_t attempt = 1; attempt <= 100; ++attempt) {
        uint64_t r = resurfi_mix64(seed + attempt * RESURFI_GOLDEN_GAMMA);
        char suffix[7];
        for (int i = 0; i < 6; ++i, r /= 62)
            suffix[i] = alphabet[r % 62];
        suffix[6] = 0;
        int n = snprintf(tmp, tmp_size, "%.*s.%s.tmp-%s", dir_len, path, name, suffix);
        if (n < 0 || (size_t)n >= tmp_size) {
            errno = ENAMETOOLONG;
            return -1;
        }
        int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            return fd;
    }
    errno = EEXIST;
    return -1;
}

resurf_status resurfi_temp_create(const resurf_allocator *alloc, const char *path, char **out_tmp, int *out_fd,
                                  resurf_error *error)
{
    size_t tmp_size = strlen(path) + 32;
    char *tmp = resurfi_alloc(alloc, tmp_size, 1);
    if (!tmp)
        return resurfi_fail(error, RESURF_ERR_OUT_OF_MEMORY, path, 0, -1, "out of memory");
    int fd = create_temp(path, tmp, tmp_size);
    if (fd < 0) {
        int e = errno;
        resurfi_free(alloc, tmp);
        const char *slash = strrchr(path, '/');
        int dir_len = slash ? (slash == path ? 1 : (int)(slash - path)) : 1;
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot create a temporary file in '%.*s': %s",
                            dir_len, slash ? path : ".", strerror(e));
    }
    /* An existing file keeps its permissions. */
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode))
        (void)fchmod(fd, st.st_mode & 07777);
    *out_tmp = tmp;
    *out_fd = fd;
    return RESURF_OK;
}

resurf_status resurfi_temp_commit(const resurf_allocator *alloc, char *tmp, const char *path, resurf_error *error)
{
    resurf_status status = RESURF_OK;
    if (rename(tmp, path) != 0) {
        status = resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot replace the file: %s", strerror(errno));
        unlink(tmp);
    }
    resurfi_free(alloc, tmp);
    return status;
}

void resurfi_temp_discard(const resurf_allocator *alloc, char *tmp)
{
    if (!tmp)
        return;
    unlink(tmp);
    resurfi_free(alloc, tmp);
}

resurf_status resurfi_save_file(const resurf_allocator *alloc, const char *path, const void *data, size_t size,
                                resurf_error *error)
{
    const char *slash = strrchr(path, '/');
    if (!(slash ? slash[1] : path[0]))
        return resurfi_fail(error, RESURF_ERR_INVALID_ARGUMENT, path, 0, -1, "the path names a folder, not a file");
    char *tmp = NULL;
    int fd = -1;
    resurf_status status = resurfi_temp_create(alloc, path, &tmp, &fd, error);
    if (status != RESURF_OK)
        return status;
    int err = resurfi_write_all(fd, data, size);
    if (close(fd) != 0 && !err)
        err = errno ? errno : EIO;
    if (err) {
        resurfi_temp_discard(alloc, tmp);
        return resurfi_fail(error, RESURF_ERR_IO, path, 0, -1, "cannot write: %s", strerror(err));
    }
    return resurfi_temp_commit(alloc, tmp, path, error);
}
