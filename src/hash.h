/* The one 64-bit mix: splitmix64's output function (Steele, Lea, Flood 2014, "Fast splittable pseudorandom number
 * generators"; Stafford's variant 13), which turns a counter or a key into 64 well-mixed bits. Feeding it
 * seed + k × RESURFI_GOLDEN_GAMMA gives output k of the splitmix64 stream. Header-only: it sits in hot loops. */
#ifndef RESURF_HASH_H
#define RESURF_HASH_H

#include <stdint.h>

/* 2^64 / φ, odd: splitmix64's step between states. */
#define RESURFI_GOLDEN_GAMMA 0x9e3779b97f4a7c15ull

static inline uint64_t resurfi_mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

#endif
