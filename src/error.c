/* Status names, error records and progress reporting: the one way resurf reports what went wrong. */
#include <stdio.h>
#include <string.h>

#include "internal.h"

const char *resurf_version(void) { return RESURF_VERSION_STRING; }

const char *resurf_status_string(resurf_status status)
{
    static const char *const names[RESURF_STATUS_COUNT] = {
        [RESURF_OK] = "ok",
        [RESURF_ERR_INVALID_ARGUMENT] = "invalid argument",
        [RESURF_ERR_INVALID_OPTIONS] = "invalid options",
        [RESURF_ERR_INVALID_MESH] = "invalid mesh",
        [RESURF_ERR_IO] = "i/o error",
        [RESURF_ERR_PARSE] = "parse error",
        [RESURF_ERR_UNSUPPORTED] = "unsupported",
        [RESURF_ERR_OUT_OF_MEMORY] = "out of memory",
        [RESURF_ERR_LIMIT] = "limit exceeded",
        [RESURF_ERR_CANCELLED] = "cancelled",
        [RESURF_ERR_INTERNAL] = "internal error",
    };
    if ((unsigned)status >= RESURF_STATUS_COUNT)
        return "unknown status";
    return names[status];
}

void resurfi_clear_error(resurf_error *error)
{
    if (!error)
        return;
    memset(error, 0, sizeof *error);
    error->offset = -1;
}

static resurf_status fail_v(resurf_error *error, resurf_status status, const char *path, long long line,
                            long long offset, const char *fmt, va_list ap)
{
    if (!error)
        return status;
    resurfi_clear_error(error);
    error->status = status;
    error->line = line;
    error->offset = offset;
    if (path)
        snprintf(error->path, sizeof error->path, "%s", path);
    vsnprintf(error->message, sizeof error->message, fmt, ap);
    return status;
}

resurf_status resurfi_fail(resurf_error *error, resurf_status status, const char *path, long long line,
                           long long offset, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fail_v(error, status, path, line, offset, fmt, ap);
    va_end(ap);
    return status;
}

resurf_status resurfi_error(resurf_error *error, resurf_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fail_v(error, status, NULL, 0, -1, fmt, ap);
    va_end(ap);
    return status;
}

size_t resurf_format_error(char *dst, size_t dst_size, const resurf_error *error)
{
    char empty = 0;
    if (!dst || dst_size == 0) {
        dst = &empty;
        dst_size = 1;
    }
    if (!error) {
        dst[0] = 0;
        return 0;
    }
    const char *message = error->message[0] ? error->message : resurf_status_string(error->status);
    int n;
    if (error->path[0] && error->line > 0)
        n = snprintf(dst, dst_size, "%s:%lld: %s", error->path, error->line, message);
    else if (error->path[0] && error->offset >= 0)
        n = snprintf(dst, dst_size, "%s: byte %lld: %s", error->path, error->offset, message);
    else if (error->path[0])
        n = snprintf(dst, dst_size, "%s: %s", error->path, message);
    else
        n = snprintf(dst, dst_size, "%s", message);
    return n < 0 ? 0 : (size_t)n;
}

const char *resurf_stage_name(resurf_stage stage)
{
    static const char *const names[RESURF_STAGE_COUNT] = {"load",    "save",     "restore", "smooth", "compare",
                                                          "prepare", "simplify", "finish",  "preview"};
    return (unsigned)stage < RESURF_STAGE_COUNT ? names[stage] : "unknown";
}

int resurfi_progress(const resurf_progress *progress, resurf_stage stage, double fraction)
{
    if (!progress || !progress->fn)
        return 0;
    if (fraction < 0)
        fraction = 0;
    if (fraction > 1)
        fraction = 1;
    return progress->fn(progress->user, stage, fraction) ? 1 : 0;
}
