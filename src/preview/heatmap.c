/* The heat map's colours: a piecewise-linear ramp through five colours, dark (no distance) to red (the largest),
 * chosen so that neighbouring values stay apart in lightness and in hue. */
#include <math.h>

#include "preview/preview_internal.h"

void rp_heat_colour(double t, unsigned char out[3])
{
    static const unsigned char stops[5][3] = {
        {30, 20, 90}, {40, 110, 230}, {30, 190, 170}, {245, 210, 40}, {200, 25, 20},
    };
    if (!(t >= 0))
        t = isnan(t) ? 1 : 0;
    if (t > 1)
        t = 1;
    double x = t * 4;
    int k = x >= 4 ? 3 : (int)x;
    double f = x - k;
    for (int c = 0; c < 3; ++c)
        out[c] = (unsigned char)(stops[k][c] + f * (stops[k + 1][c] - stops[k][c]) + 0.5);
}
