/* What every format reader (io_obj.c, io_ply.c, io_off.c, io_stl.c) calls back during one load (io_internal.h):
 * progress reports, the triangle limit and the messages of parse errors, all naming the file and where in it. */
#include <stdarg.h>
#include <stdio.h>

#include "io_internal.h"

resurf_status resurfi_load_progress(resurfi_load *ld, const char *pos)
{
    double fraction = ld->size ? (double)(pos - ld->data) / (double)ld->size : 1.0;
    if (resurfi_progress(ld->progress, RESURF_STAGE_LOAD, fraction))
        return resurfi_fail(ld->error, RESURF_ERR_CANCELLED, ld->path, 0, -1, "cancelled by the progress callback");
    return RESURF_OK;
}

resurf_status resurfi_check_triangle_limit(resurfi_load *ld, size_t triangle_count, long long line,
                                           long long offset)
{
    if (ld->max_triangles == 0 || triangle_count <= ld->max_triangles)
        return RESURF_OK;
    return resurfi_fail(ld->error, RESURF_ERR_LIMIT, ld->path, line, line > 0 ? -1 : offset,
                        "more than %zu triangles (the max_triangles limit)", ld->max_triangles);
}

resurf_status resurfi_parse_fail(resurfi_load *ld, long long line, long long offset, const char *fmt, ...)
{
    char message[sizeof ld->error->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return resurfi_fail(ld->error, RESURF_ERR_PARSE, ld->path, line, line > 0 ? -1 : offset, "%s", message);
}

resurf_status resurfi_load_oom(resurfi_load *ld, const char *what)
{
    return resurfi_fail(ld->error, RESURF_ERR_OUT_OF_MEMORY, ld->path, 0, -1, "out of memory reading the %s", what);
}
