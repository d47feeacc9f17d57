/* Union-find over an array of parent indices (parent[x] == x: x is a root), with path halving. A union makes the
 * lower of the two roots the root, so every set's root is its lowest member and the sets' numbering never depends
 * on the order in which unions come. Header-only: the finds sit in hot loops of their callers. */
#ifndef RESURF_UNION_FIND_H
#define RESURF_UNION_FIND_H

#include <stdint.h>

static inline uint32_t resurfi_uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static inline void resurfi_uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = resurfi_uf_find(parent, a);
    b = resurfi_uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

#endif
