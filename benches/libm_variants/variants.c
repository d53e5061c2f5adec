/* Hashes of glibc's libm results over the inputs Penumbra gives them (every float of each f32
 * range; 10^7 random f64 arguments), one line per function. check.sh runs it twice, with
 * glibc's FMA variants and with its pre-FMA ones, and prints the lines that differ. */
#define _GNU_SOURCE
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static float f_of(uint32_t u) { float f; memcpy(&f, &u, 4); return f; }
static uint32_t bits_f(float f) { uint32_t u; memcpy(&u, &f, 4); return u; }
static uint64_t bits_d(double d) { uint64_t u; memcpy(&u, &d, 8); return u; }
static uint64_t mix(uint64_t h, uint64_t v) { return (h ^ v) * 0x100000001b3ull; }
#define START 0xcbf29ce484222325ull

/* Every float from a to b (both >= 0, or both <= 0 with a nearer zero). */
#define EACH(a, b, ...) for (uint32_t u = bits_f(a); u <= bits_f(b); u++) { float x = f_of(u); __VA_ARGS__; }

int main(void) {
    uint64_t h;
    h = START; EACH(0.0f, 8.0f, { float s, c; sincosf(x, &s, &c); h = mix(h, bits_f(sinf(x))); h = mix(h, bits_f(cosf(x)));
        h = mix(h, bits_f(s)); h = mix(h, bits_f(c)); h = mix(h, bits_f(sinf(-x))); h = mix(h, bits_f(cosf(-x))); })
    printf("f32 sinf cosf sincosf on [-8, 8]   %016llx\n", (unsigned long long)h);
    h = START; EACH(0.0f, 8.0f, h = mix(h, bits_f(tanf(x)))) printf("f32 tanf on [0, 8]                  %016llx\n", (unsigned long long)h);
    h = START; EACH(0.0f, 1.0f, h = mix(h, bits_f(powf(x, 1.0f / 2.4f)))) printf("f32 powf(x, 1/2.4) on [0, 1]        %016llx\n", (unsigned long long)h);
    h = START; EACH(0.052f, 1.0f, h = mix(h, bits_f(powf(x, 2.4f)))) printf("f32 powf(x, 2.4) on [0.052, 1]      %016llx\n", (unsigned long long)h);
    h = START; EACH(0.0f, 1.0f, h = mix(h, bits_f(powf(x, 1.0f / 2.4f - 1.0f)))) printf("f32 powf(x, 1/2.4 - 1) on [0, 1]    %016llx\n", (unsigned long long)h);
    h = START; EACH(0.0f, 1.0f, { h = mix(h, bits_f(acosf(x))); h = mix(h, bits_f(acosf(-x))); h = mix(h, bits_f(atanf(x))); })
    printf("f32 acosf on [-1, 1], atanf [0, 1]  %016llx\n", (unsigned long long)h);
    h = START; for (uint32_t u = 0x80000000u; u <= bits_f(-100.0f); u++) h = mix(h, bits_f(expf(f_of(u))));
    printf("f32 expf on [-100, 0]               %016llx\n", (unsigned long long)h);
    uint64_t s = 0x9e3779b97f4a7c15ull, hs = START, hc = START, he = START;
    for (long i = 0; i < 10000000; i++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        double x = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * 2.0 * 3.141592653589793;
        hs = mix(hs, bits_d(sin(x))); hc = mix(hc, bits_d(cos(x))); he = mix(he, bits_d(exp(x)));
    }
    printf("f64 sin, 10^7 random in [-pi, pi]   %016llx\n", (unsigned long long)hs);
    printf("f64 cos, 10^7 random in [-pi, pi]   %016llx\n", (unsigned long long)hc);
    printf("f64 exp, 10^7 random in [-pi, pi]   %016llx\n", (unsigned long long)he);
    return 0;
}
