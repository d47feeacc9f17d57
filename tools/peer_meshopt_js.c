/* npm meshoptimizer under node as a peer of the simplification benchmark (tools/peers.h): the mesh goes to
 * tools/peer-meshopt.mjs through a temporary file, which says its layout, and the LOD comes back the same way. */
#include <spawn.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "peers.h"

extern char **environ;

static int fail(char *why, size_t why_size, const char *text, const char *detail)
{
    snprintf(why, why_size, "%s%s%s", text, detail ? ": " : "", detail ? detail : "");
    return 0;
}

static int write_request(const char *path, const resurf_mesh *m, size_t target_tris, peer_meshopt_js_mode mode,
                         int repeat)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return 0;
    uint32_t head[4] = {0, (uint32_t)mode, (uint32_t)(repeat > 0 ? repeat : 1), 0};
    memcpy(head, "RSPI", 4);
    uint64_t sizes[3] = {m->vertex_count, 3 * (uint64_t)m->triangle_count, 3 * (uint64_t)target_tris};
    int ok = fwrite(head, sizeof head, 1, f) == 1 && fwrite(sizes, sizeof sizes, 1, f) == 1;
    for (size_t i = 0; ok && i < 3 * m->vertex_count; ++i) {
        float x = (float)m->positions[i];
        ok = fwrite(&x, sizeof x, 1, f) == 1;
    }
    ok = ok && fwrite(m->indices, sizeof *m->indices, 3 * m->triangle_count, f) == 3 * m->triangle_count;
    return fclose(f) == 0 && ok;
}

/* The reply as a mesh of the vertices its triangles use: at the input's double positions for simplify (as the
 * native peer), at node's float positions for simplifyWithUpdate, which moved them. */
static int read_reply(const char *path, const resurf_mesh *m, peer_meshopt_js_mode mode, resurf_mesh **out,
                      double *seconds, char *why, size_t why_size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return fail(why, why_size, "node wrote no reply", NULL);
    uint32_t head[2];
    uint64_t counts[2];
    double timing[2];
    float *pos = NULL;
    uint32_t *idx = NULL, *remap = NULL;
    int ok = fread(head, sizeof head, 1, f) == 1 && !memcmp(head, "RSPO", 4) && fread(counts, sizeof counts, 1, f) == 1 &&
             fread(timing, sizeof timing, 1, f) == 1 && counts[1] == m->vertex_count &&
             counts[0] <= 3 * (uint64_t)m->triangle_count && counts[0] % 3 == 0;
    size_t ni = ok ? (size_t)counts[0] : 0, nv = m->vertex_count;
    if (ok) {
        pos = malloc((3 * nv + 1) * sizeof *pos);
        idx = malloc((ni + 1) * sizeof *idx);
        remap = malloc((nv + 1) * sizeof *remap);
        ok = pos && idx && remap && fread(pos, sizeof *pos, 3 * nv, f) == 3 * nv && fread(idx, sizeof *idx, ni, f) == ni;
    }
    fclose(f);
    for (size_t i = 0; ok && i < ni; ++i)
        ok = idx[i] < nv;
    size_t used = 0;
    if (ok) {
        memset(remap, 0xff, nv * sizeof *remap);
        for (size_t i = 0; i < ni; ++i)
            if (remap[idx[i]] == UINT32_MAX)
                remap[idx[i]] = (uint32_t)used++;
        ok = resurf_mesh_create(used, ni / 3, 0, out, NULL) == RESURF_OK;
    }
    if (ok) {
        for (size_t v = 0; v < nv; ++v)
            if (remap[v] != UINT32_MAX)
                for (int c = 0; c < 3; ++c)
                    (*out)->positions[3 * (size_t)remap[v] + c] =
                        mode == PEER_MESHOPT_JS_UPDATE ? (double)pos[3 * v + c] : m->positions[3 * v + c];
        for (size_t i = 0; i < ni; ++i)
            (*out)->indices[i] = remap[idx[i]];
        *seconds = timing[0];
    }
    free(pos);
    free(idx);
    free(remap);
    return ok ? 1 : fail(why, why_size, "node's reply is not what was asked for", NULL);
}

int peer_meshopt_js(const char *script, const resurf_mesh *m, size_t target_tris, peer_meshopt_js_mode mode,
                    int repeat, resurf_mesh **out, double *seconds, char *why, size_t why_size)
{
    *out = NULL;
    why[0] = 0;
    if (access(script, R_OK))
        return fail(why, why_size, "no script", script);
    char in[64] = "/tmp/bench-simplify-XXXXXX", reply[80];
    int fd = mkstemp(in);
    if (fd < 0)
        return fail(why, why_size, "no temporary file", NULL);
    close(fd);
    snprintf(reply, sizeof reply, "%s.out", in);
    int ok = write_request(in, m, target_tris, mode, repeat);
    if (!ok) {
        fail(why, why_size, "could not write", in);
    } else {
        char *argv[] = {"node", (char *)script, in, reply, NULL};
        pid_t pid;
        int status = 0;
        if (posix_spawnp(&pid, "node", NULL, NULL, argv, environ) != 0)
            ok = fail(why, why_size, "node not found on PATH", NULL);
        else if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
            ok = fail(why, why_size, "node failed (is npm meshoptimizer in tools/node? tools/bench-setup-peers.sh)",
                      NULL);
        else
            ok = read_reply(reply, m, mode, out, seconds, why, why_size);
    }
    unlink(in);
    unlink(reply);
    return ok;
}
