/* Fins and double-sided sheets (resurf_simplify_options.drop_fins): triangles over the same three positions as
 * another, found before the working mesh is built. A scan's zero-thickness fins are left out; a double-sided sheet
 * (a card, a flag, a panel modelled as two sheets over the same positions) keeps one side in the working mesh, and
 * its other side is written back mirrored in every level (output.c). */
#include <stdlib.h>

#include "simplify_internal.h"
#include "../union_find.h"

/* Triangle t, filed under its lowest position p, as the other two positions lo < hi and the way it runs: +1 for
 * (p, lo, hi), −1 for (p, hi, lo). */
static int fin_key(const resurf_mesh *in, const uint32_t *remap, uint32_t t, uint32_t p, uint32_t *lo, uint32_t *hi)
{
    const uint32_t *i = in->indices + 3 * (size_t)t;
    int k = remap[i[0]] == p ? 0 : remap[i[1]] == p ? 1 : 2;
    uint32_t u = remap[i[(k + 1) % 3]], w = remap[i[(k + 2) % 3]];
    *lo = u < w ? u : w;
    *hi = u < w ? w : u;
    return u < w ? 1 : -1;
}

/* Are input triangles t and u of the same group? A fin's two sides in two materials (a double-sided sign) are two
 * surfaces the input means, not a modelling slip. */
static int same_group(const resurf_mesh *in, uint32_t t, uint32_t u)
{
    return !in->triangle_groups || in->triangle_groups[t] == in->triangle_groups[u];
}

/* Is triangle m, filed under position p as t is, over t's three positions and of t's group? 0 when not, else the
 * way m runs (fin_key). */
static int same_set(const resurf_mesh *in, const uint32_t *remap, uint32_t p, uint32_t t, uint32_t m)
{
    uint32_t lo, hi, lo2, hi2;
    fin_key(in, remap, t, p, &lo, &hi);
    int run = fin_key(in, remap, m, p, &lo2, &hi2);
    return lo2 == lo && hi2 == hi && same_group(in, t, m) ? run : 0;
}

/* A double-sided sheet (a leaf card, a flag, a sign modelled as two sheets over the same positions) is fins
 * throughout, and dropping its pairs would drop the sheet: the positions only its triangles use would leave the
 * result, and with them the whole card. A scan's fins are strays among surface triangles (the dragon-48k scan:
 * 1,052 pairs in 973 groups, 179 of them with one position of their own, 5 with two or three). So the dropped
 * triangles are grouped by the positions they share, and a group with at least SHEET_OWN positions that no kept
 * triangle uses, and at most SHEET_ATTACHED that one does, is a sheet: of each of its opposite pairs one
 * triangle stays (choose_sides) and the sheet is simplified as one side; the other triangle of the pair is its
 * mirror (s->mirror), and every level writes the mirror of each triangle descended from that side back, so the
 * back of a card with a one-sided material stays visible. A sheet attached along a longer line is kept so only
 * with attached_sheets KEEP: where it meets the surface its line is edges of three triangles, which move only along
 * the line (collapse.c). XGL_Wuson's dewlap, 15 positions of its own along 15 of the body: kept, the 25% level's
 * Hausdorff distance falls from 1.66% to 0.70% of the diagonal, but at 10% the line costs the body's shape (4.4%
 * dropped, 6.5% kept while the line held still); the measured default makes both and keeps the nearer
 * (simplify.c). */
enum { SHEET_OWN = 4, SHEET_ATTACHED = 2 };
enum { USE_KEPT = 1, USE_DROPPED = 2 }; /* a position's use by triangles that stay and that are left out */

/* Which side of a sheet the working mesh keeps. The first-written triangle of each pair is not always the same side
 * of the sheet: some exporters write every face and its mirror in turn, so that the first-written triangles of one
 * panel face both ways, and their edges then run the same way twice (a fold the simplifier may not collapse). And a
 * panel continued by single-sided triangles (a box whose lid alone is double-sided; a column written double-sided
 * but for a few faces) is one surface with them only if its kept side runs the way they do. So the side follows
 * orientation: from the triangles that stay, across every edge where exactly one side is settled (one kept
 * triangle continues a sheet; at a junction of two kept triangles and a sheet, the sheet's side is free), each
 * pair takes the triangle that runs the edge the other way, and the choice spreads through the sheet edge by
 * edge. A sheet that touches no such edge starts from its first-written triangle, as before. Before this rule the
 * sheets of `porch-column-02` (Sweet Home 3D's furniture), 3,082 pairs and 24 single triangles, kept 404 edges
 * running the same way twice, and its 25% level stopped blocked at 3.0% of the diagonal; with it, 0 such edges. */
typedef struct sheet_sides {
    simplifier *s;
    const uint32_t *remap, *filed, *offset;
    uint8_t *drop;
    uint32_t *group;       /* union-find over the dropped triangles' positions */
    const uint32_t *count; /* per group root: its positions of its own, those shared with kept triangles */
    const uint8_t *use;    /* per position: nonzero when a dropped triangle uses it */
    size_t attached_max;   /* a sheet shares at most this many positions with kept triangles */
} sheet_sides;

typedef struct sheet_edge {
    uint64_t key; /* lo << 32 | hi of the edge's two positions */
    uint32_t t;
} sheet_edge;

static int edge_order(const void *x, const void *y)
{
    const sheet_edge *a = x, *b = y;
    return a->key != b->key ? (a->key < b->key ? -1 : 1) : (a->t > b->t) - (a->t < b->t);
}

static uint64_t edge_key(uint32_t a, uint32_t b) { return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a; }

/* Triangle t's positions, welded. */
static void corners_of(const sheet_sides *ss, uint32_t t, uint32_t c[3])
{
    const uint32_t *i = ss->s->in->indices + 3 * (size_t)t;
    c[0] = ss->remap[i[0]], c[1] = ss->remap[i[1]], c[2] = ss->remap[i[2]];
}

/* Is t a left-out triangle of a group that is a sheet? */
static int in_sheet(sheet_sides *ss, uint32_t t)
{
    if (ss->drop[t] != FIN_DROP)
        return 0;
    uint32_t c[3];
    corners_of(ss, t, c);
    const uint32_t *n = ss->count + 2 * resurfi_uf_find(ss->group, c[0]);
    return n[0] >= SHEET_OWN && n[1] <= ss->attached_max;
}

/* Has the set of triangles over t's three positions (of t's group) a triangle that stays already? */
static int side_taken(const sheet_sides *ss, uint32_t t)
{
    const resurf_mesh *in = ss->s->in;
    uint32_t c[3];
    corners_of(ss, t, c);
    uint32_t p = c[0] < c[1] ? (c[0] < c[2] ? c[0] : c[2]) : (c[1] < c[2] ? c[1] : c[2]);
    for (uint32_t y = ss->offset[p]; y < ss->offset[p + 1]; ++y) {
        uint32_t m = ss->filed[y];
        if ((ss->drop[m] == FIN_KEEP || ss->drop[m] == FIN_SHEET) && same_set(in, ss->remap, p, t, m))
            return 1;
    }
    return 0;
}

/* Is triangle c (its positions) a proper one that touches a position of a left-out triangle? */
static int near_left_out(const sheet_sides *ss, const uint32_t c[3])
{
    return c[0] != c[1] && c[1] != c[2] && c[0] != c[2] &&
           ((ss->use[c[0]] | ss->use[c[1]] | ss->use[c[2]]) & USE_DROPPED);
}

static int stays(uint8_t d) { return d == 0 || d == FIN_KEEP || d == FIN_SHEET; }

/* Spreads the kept sides from the triangles queued in q[*head .. *tail) (see above). */
static void spread(sheet_sides *ss, const sheet_edge *edges, size_t edge_count, uint32_t *q, size_t *head,
                   size_t *tail, size_t *dropped)
{
    while (*head < *tail) {
        uint32_t d = q[(*head)++], c[3];
        corners_of(ss, d, c);
        for (int k = 0; k < 3; ++k) {
            uint32_t a = c[k], b = c[(k + 1) % 3];
            uint64_t key = edge_key(a, b);
            size_t lo = 0, hi = edge_count; /* the edge's first entry */
            while (lo < hi) {
                size_t mid = (lo + hi) / 2;
                if (edges[mid].key < key)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            size_t end = lo, settled = 0;
            while (end < edge_count && edges[end].key == key)
                settled += stays(ss->drop[edges[end++].t]);
            if (settled != 1)
                continue;
            for (size_t x = lo; x < end; ++x) {
                uint32_t u = edges[x].t, e[3];
                corners_of(ss, u, e);
                int reverse = (e[0] == b && e[1] == a) || (e[1] == b && e[2] == a) || (e[2] == b && e[0] == a);
                if (reverse && in_sheet(ss, u) && !side_taken(ss, u)) {
                    ss->drop[u] = FIN_SHEET;
                    --*dropped;
                    q[(*tail)++] = u;
                }
            }
        }
    }
}

static resurf_status choose_sides(sheet_sides *ss, size_t *dropped)
{
    simplifier *s = ss->s;
    const resurf_mesh *in = s->in;
    size_t nt = in->triangle_count, edge_count = 0;
    /* every edge of the triangles that touch a left-out one's positions, sorted */
    for (size_t t = 0; t < nt; ++t) {
        uint32_t c[3];
        corners_of(ss, (uint32_t)t, c);
        edge_count += near_left_out(ss, c);
    }
    edge_count *= 3;
    sheet_edge *edges = resurfi_alloc(s->alloc, edge_count ? edge_count : 1, sizeof *edges);
    uint32_t *q = resurfi_alloc(s->alloc, nt ? nt : 1, sizeof *q);
    if (!edges || !q) {
        resurfi_free(s->alloc, edges);
        resurfi_free(s->alloc, q);
        return RESURF_ERR_OUT_OF_MEMORY;
    }
    size_t n = 0, head = 0, tail = 0;
    for (size_t t = 0; t < nt; ++t) {
        uint32_t c[3];
        corners_of(ss, (uint32_t)t, c);
        if (!near_left_out(ss, c))
            continue;
        for (int k = 0; k < 3; ++k)
            edges[n++] = (sheet_edge){edge_key(c[k], c[(k + 1) % 3]), (uint32_t)t};
        if (stays(ss->drop[t]))
            q[tail++] = (uint32_t)t; /* the triangles that stay settle the sides next to them first */
    }
    qsort(edges, n, sizeof *edges, edge_order);
    spread(ss, edges, n, q, &head, &tail, dropped);
    /* the sheets no edge settled: from each one's first-written triangle, in the order of their positions */
    for (size_t p = 0; p < s->pos_count; ++p)
        for (uint32_t x = ss->offset[p]; x < ss->offset[p + 1]; ++x) {
            uint32_t t = ss->filed[x];
            if (!in_sheet(ss, t) || side_taken(ss, t))
                continue;
            int first = 1;
            for (uint32_t y = ss->offset[p]; y < ss->offset[p + 1] && first; ++y) {
                uint32_t m = ss->filed[y];
                first = !(m < t && same_set(in, ss->remap, (uint32_t)p, t, m));
            }
            if (!first)
                continue;
            ss->drop[t] = FIN_SHEET;
            --*dropped;
            q[tail++] = t;
            spread(ss, edges, n, q, &head, &tail, dropped);
        }
    resurfi_free(s->alloc, edges);
    resurfi_free(s->alloc, q);
    return RESURF_OK;
}

static resurf_status keep_sheets(simplifier *s, const uint32_t *remap, const uint32_t *filed, const uint32_t *offset,
                                 uint8_t *drop, size_t *dropped)
{
    const resurf_mesh *in = s->in;
    size_t nt = in->triangle_count, pc = s->pos_count;
    /* group: union-find over the dropped triangles' positions; count: per group root, its positions of its own
     * and those it shares with kept triangles; use: per position, USE_* bits */
    uint32_t *group = resurfi_alloc(s->alloc, pc, sizeof *group);
    uint32_t *count = resurfi_calloc(s->alloc, 2 * pc, sizeof *count);
    uint8_t *use = resurfi_calloc(s->alloc, pc, 1);
    resurf_status st = RESURF_ERR_OUT_OF_MEMORY;
    if (!group || !count || !use)
        goto done;
    for (size_t p = 0; p < pc; ++p)
        group[p] = (uint32_t)p;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a == b || b == c || a == c)
            continue;
        uint8_t bit = drop[t] == FIN_DROP ? USE_DROPPED : USE_KEPT;
        use[a] |= bit, use[b] |= bit, use[c] |= bit;
        if (bit == USE_DROPPED) {
            resurfi_uf_union(group, a, b);
            resurfi_uf_union(group, a, c);
        }
    }
    for (size_t p = 0; p < pc; ++p)
        if (use[p] & USE_DROPPED)
            count[2 * resurfi_uf_find(group, (uint32_t)p) + (use[p] != USE_DROPPED)]++;
    for (size_t p = 0; p < pc; ++p) {
        const uint32_t *c = count + 2 * p;
        s->attached_sheets += resurfi_uf_find(group, (uint32_t)p) == p && c[0] >= SHEET_OWN && c[1] > SHEET_ATTACHED;
    }
    size_t attached_max = s->opt.attached_sheets == RESURF_SHEETS_KEEP ? SIZE_MAX : SHEET_ATTACHED;
    sheet_sides ss = {s, remap, filed, offset, drop, group, count, use, attached_max};
    if (choose_sides(&ss, dropped) != RESURF_OK)
        goto done;
    /* each kept side's mirror: an opposite triangle over its three positions, left out and not yet taken */
    for (size_t p = 0; p < pc; ++p)
        for (uint32_t x = offset[p]; x < offset[p + 1]; ++x) {
            uint32_t t = filed[x];
            if (drop[t] != FIN_SHEET)
                continue;
            int opposite = -same_set(in, remap, (uint32_t)p, t, t);
            for (uint32_t y = offset[p]; y < offset[p + 1]; ++y) {
                uint32_t m = filed[y];
                if (drop[m] != FIN_DROP || same_set(in, remap, (uint32_t)p, t, m) != opposite)
                    continue;
                if (!s->mirror) {
                    if (!(s->mirror = resurfi_alloc(s->alloc, nt, sizeof *s->mirror)))
                        goto done;
                    memset(s->mirror, 0xff, nt * sizeof *s->mirror);
                }
                s->mirror[t] = m;
                drop[m] = FIN_MIRROR;
                --*dropped;
                break;
            }
        }
    st = RESURF_OK;
done:
    resurfi_free(s->alloc, group);
    resurfi_free(s->alloc, count);
    resurfi_free(s->alloc, use);
    return st;
}

/* The triangles drop_fins leaves out (see resurf_simplify_options): (*out_drop)[t] == FIN_DROP for them, or
 * *out_drop = NULL when there are none. Triangles over the same three positions share their lowest position, so
 * each is compared only with the few others filed under it. Of n+ triangles running one way and n− the other,
 * min(n+, n−) opposite pairs go, and of the rest all but the first. */
resurf_status resurfi_find_fins(simplifier *s, const uint32_t *remap, uint8_t **out_drop)
{
    const resurf_mesh *in = s->in;
    size_t nt = in->triangle_count, pc = s->pos_count;
    *out_drop = NULL;
    uint32_t *offset = resurfi_calloc(s->alloc, pc + 1, sizeof *offset);
    uint32_t *filed = resurfi_alloc(s->alloc, nt, sizeof *filed);
    uint8_t *drop = resurfi_calloc(s->alloc, nt, 1);
    size_t dropped = 0;
    if (!offset || !filed || !drop)
        goto oom;
    /* file every non-degenerate triangle under its lowest position */
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a != b && b != c && a != c)
            offset[(a < b ? (a < c ? a : c) : (b < c ? b : c)) + 1]++;
    }
    for (size_t p = 0; p < pc; ++p)
        offset[p + 1] += offset[p];
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *i = in->indices + 3 * t;
        uint32_t a = remap[i[0]], b = remap[i[1]], c = remap[i[2]];
        if (a != b && b != c && a != c)
            filed[offset[a < b ? (a < c ? a : c) : (b < c ? b : c)]++] = (uint32_t)t;
    }
    for (size_t p = pc; p > 0; --p) /* back to the starts */
        offset[p] = offset[p - 1];
    offset[0] = 0;
    for (size_t p = 0; p < pc; ++p) {
        for (uint32_t x = offset[p]; x < offset[p + 1]; ++x) {
            uint32_t t = filed[x];
            if (drop[t])
                continue; /* decided with an earlier member of its group */
            int balance = same_set(in, remap, (uint32_t)p, t, t);
            size_t members = 1;
            for (uint32_t y = x + 1; y < offset[p + 1]; ++y) {
                int run = drop[filed[y]] ? 0 : same_set(in, remap, (uint32_t)p, t, filed[y]);
                balance += run, members += run != 0;
            }
            if (members == 1)
                continue;
            /* the first member on the side with more members stays (none when the sides balance) */
            int keep = balance > 0 ? 1 : balance < 0 ? -1 : 0;
            for (uint32_t y = x; y < offset[p + 1]; ++y) {
                uint32_t m = filed[y];
                int run = drop[m] ? 0 : same_set(in, remap, (uint32_t)p, t, m);
                if (!run)
                    continue;
                if (run == keep)
                    drop[m] = FIN_KEEP, keep = 0;
                else
                    drop[m] = FIN_DROP, ++dropped;
            }
        }
    }
    if (dropped && keep_sheets(s, remap, filed, offset, drop, &dropped) != RESURF_OK)
        goto oom;
    s->rep.dropped_fins = dropped;
    if (dropped || s->mirror) { /* a sheet's mirrors are left out of the working mesh too */
        *out_drop = drop;
        drop = NULL;
    }
    resurfi_free(s->alloc, offset);
    resurfi_free(s->alloc, filed);
    resurfi_free(s->alloc, drop);
    return RESURF_OK;
oom:
    resurfi_free(s->alloc, offset);
    resurfi_free(s->alloc, filed);
    resurfi_free(s->alloc, drop);
    return RESURF_ERR_OUT_OF_MEMORY;
}
