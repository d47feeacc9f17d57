/* src/error.c: error records, their formatting (every form, truncation), status names and progress calls. */
#include <string.h>

#include "testutil.h"

static resurf_error make_error(const char *path, long long line, long long offset, const char *message)
{
    resurf_error e;
    resurfi_fail(&e, RESURF_ERR_PARSE, path, line, offset, "%s", message);
    return e;
}

START_TEST(error_format_forms)
{
    char buf[512];
    resurf_error e = make_error("a.obj", 12, -1, "face 3 refers to vertex 9 of 4");
    ck_assert_uint_eq(resurf_format_error(buf, sizeof buf, &e), strlen("a.obj:12: face 3 refers to vertex 9 of 4"));
    ck_assert_str_eq(buf, "a.obj:12: face 3 refers to vertex 9 of 4");

    e = make_error("b.stl", 0, 84, "truncated");
    resurf_format_error(buf, sizeof buf, &e);
    ck_assert_str_eq(buf, "b.stl: byte 84: truncated");

    e = make_error("b.stl", 0, 0, "empty"); /* offset 0 is a real offset */
    resurf_format_error(buf, sizeof buf, &e);
    ck_assert_str_eq(buf, "b.stl: byte 0: empty");

    e = make_error("c.ply", 0, -1, "no vertex element");
    resurf_format_error(buf, sizeof buf, &e);
    ck_assert_str_eq(buf, "c.ply: no vertex element");

    e = make_error(NULL, 5, 9, "bad options"); /* no path: line and offset are not shown */
    resurf_format_error(buf, sizeof buf, &e);
    ck_assert_str_eq(buf, "bad options");

    /* The line wins over the offset when both are set. */
    e = make_error("d.obj", 3, 40, "x");
    resurf_format_error(buf, sizeof buf, &e);
    ck_assert_str_eq(buf, "d.obj:3: x");

    /* An empty message falls back on the status name. */
    resurfi_clear_error(&e);
    e.status = RESURF_ERR_OUT_OF_MEMORY;
    resurf_format_error(buf, sizeof buf, &e);
    ck_assert_str_eq(buf, "out of memory");
}
END_TEST

/* Truncation: always NUL-terminated, the return value is the full length, NULL/0 buffers only measure. */
START_TEST(error_format_truncates)
{
    resurf_error e = make_error("model.obj", 7, -1, "unexpected token");
    const char *full = "model.obj:7: unexpected token";
    size_t n = strlen(full);
    for (size_t size = 1; size <= n + 2; ++size) {
        char buf[64];
        memset(buf, '#', sizeof buf);
        ck_assert_uint_eq(resurf_format_error(buf, size, &e), n);
        size_t kept = size - 1 < n ? size - 1 : n;
        ck_assert_uint_eq(strlen(buf), kept);
        ck_assert(strncmp(buf, full, kept) == 0);
        ck_assert_int_eq(buf[size], '#'); /* nothing written past dst_size */
    }
    ck_assert_uint_eq(resurf_format_error(NULL, 0, &e), n);
    char one = 'x';
    ck_assert_uint_eq(resurf_format_error(&one, 0, &e), n);
    ck_assert_int_eq(one, 'x');
    char buf[8] = "junk";
    ck_assert_uint_eq(resurf_format_error(buf, sizeof buf, NULL), 0);
    ck_assert_str_eq(buf, "");
}
END_TEST

/* Long paths and messages are cut to their fields, NUL-terminated. */
START_TEST(error_fields_truncate)
{
    char path[600], message[600];
    memset(path, 'p', sizeof path - 1);
    path[sizeof path - 1] = 0;
    memset(message, 'm', sizeof message - 1);
    message[sizeof message - 1] = 0;
    resurf_error e = make_error(path, 1, -1, message);
    ck_assert_uint_eq(strlen(e.path), sizeof e.path - 1);
    ck_assert_uint_eq(strlen(e.message), sizeof e.message - 1);
    char buf[1024];
    ck_assert_uint_eq(resurf_format_error(buf, sizeof buf, &e), 255 + strlen(":1: ") + 255);
}
END_TEST

START_TEST(error_fail_fills_record)
{
    resurf_error e;
    memset(&e, 0x5a, sizeof e);
    ck_assert_int_eq(resurfi_error(&e, RESURF_ERR_INVALID_MESH, "face %d refers to vertex %d", 12, 40),
                     RESURF_ERR_INVALID_MESH);
    ck_assert_int_eq(e.status, RESURF_ERR_INVALID_MESH);
    ck_assert_str_eq(e.message, "face 12 refers to vertex 40");
    ck_assert_str_eq(e.path, "");
    ck_assert_int_eq(e.line, 0);
    ck_assert_int_eq(e.offset, -1);
    ck_assert_int_eq(resurfi_fail(&e, RESURF_ERR_IO, "/tmp/x", 0, 17, "short read"), RESURF_ERR_IO);
    ck_assert_str_eq(e.path, "/tmp/x");
    ck_assert_int_eq(e.offset, 17);
    /* A NULL record is allowed and the status still comes back. */
    ck_assert_int_eq(resurfi_error(NULL, RESURF_ERR_LIMIT, "too big"), RESURF_ERR_LIMIT);
    resurfi_clear_error(&e);
    ck_assert_int_eq(e.status, RESURF_OK);
    ck_assert_str_eq(e.message, "");
    ck_assert_int_eq(e.offset, -1);
    resurfi_clear_error(NULL);
}
END_TEST

/* Every status has its own non-empty name; values outside the enum get a fixed fallback, never NULL. */
START_TEST(error_status_strings)
{
    ck_assert_str_eq(resurf_status_string(RESURF_OK), "ok");
    ck_assert_str_eq(resurf_status_string(RESURF_ERR_PARSE), "parse error");
    for (int s = 0; s < RESURF_STATUS_COUNT; ++s) {
        const char *name = resurf_status_string((resurf_status)s);
        ck_assert_ptr_nonnull(name);
        ck_assert_uint_gt(strlen(name), 0);
        for (int t = 0; t < s; ++t)
            ck_assert_str_ne(name, resurf_status_string((resurf_status)t));
    }
    ck_assert_str_eq(resurf_status_string(RESURF_STATUS_COUNT), "unknown status");
    ck_assert_str_eq(resurf_status_string((resurf_status)-1), "unknown status");
    ck_assert_str_eq(resurf_version(), RESURF_VERSION_STRING);
}
END_TEST

typedef struct progress_log {
    int calls;
    double last;
    resurf_stage stage;
    bool answer;
} progress_log;

static bool record_progress(void *user, resurf_stage stage, double fraction)
{
    progress_log *log = user;
    log->calls++;
    log->last = fraction;
    log->stage = stage;
    return log->answer;
}

/* The callback sees the stage and a fraction clamped to [0,1]; its answer comes back; no callback = continue. */
START_TEST(error_progress)
{
    progress_log log = {0, -1, RESURF_STAGE_COUNT, false};
    resurf_progress p = {record_progress, &log};
    ck_assert_int_eq(resurfi_progress(&p, RESURF_STAGE_LOAD, 0.25), 0);
    ck_assert_int_eq(log.calls, 1);
    ck_assert_double_eq(log.last, 0.25);
    ck_assert_int_eq(log.stage, RESURF_STAGE_LOAD);
    resurfi_progress(&p, RESURF_STAGE_LOAD, 1.5);
    ck_assert_double_eq(log.last, 1);
    resurfi_progress(&p, RESURF_STAGE_LOAD, -3);
    ck_assert_double_eq(log.last, 0);
    log.answer = true;
    ck_assert_int_ne(resurfi_progress(&p, RESURF_STAGE_RESTORE, 0.5), 0);
    ck_assert_int_eq(log.stage, RESURF_STAGE_RESTORE);
    resurf_progress none = {NULL, NULL};
    ck_assert_int_eq(resurfi_progress(&none, RESURF_STAGE_SAVE, 0.5), 0);
    ck_assert_int_eq(resurfi_progress(NULL, RESURF_STAGE_SAVE, 0.5), 0);
    ck_assert_int_eq(log.calls, 4);
}
END_TEST

Suite *make_suite(void)
{
    Suite *s = suite_create("error");
    TCase *tc = tcase_create("error");
    tcase_add_test(tc, error_format_forms);
    tcase_add_test(tc, error_format_truncates);
    tcase_add_test(tc, error_fields_truncate);
    tcase_add_test(tc, error_fail_fills_record);
    tcase_add_test(tc, error_status_strings);
    tcase_add_test(tc, error_progress);
    suite_add_tcase(s, tc);
    return s;
}

RESURF_TEST_MAIN()
