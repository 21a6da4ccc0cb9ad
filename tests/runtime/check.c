/* The runtime's C interface as an engine links it: opens a bake, reads its raw frames
 * (wind.f32) itself, and checks windloom_wind_at and windloom_wind_at_many against them at
 * every cell of every frame, in windloom's, Unity's and Unreal's axes.
 * Usage: check BAKE_DIR HEIGHT   (HEIGHT: metres above the ground the baked wind stands for)
 * Built and run by tests/export/runtime.rs. */
#include "windloom.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

static void expect(int ok, const char *what, double got, double want) {
    if (!ok && failures++ < 10) {
        fprintf(stderr, "mismatch: %s: got %.9g, want %.9g\n", what, got, want);
    }
}

/* The raw value within the rounding of a cell centre's position in floats. */
static int near(float got, float want) {
    return fabsf(got - want) <= 1e-4f * (1.0f + fabsf(want));
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: check BAKE_DIR HEIGHT\n");
        return 2;
    }
    const char *folder = argv[1];
    float y = (float)atof(argv[2]);

    /* A folder that is not there: NULL, and the reason names it. */
    if (windloom_open("/no/such/bake", WINDLOOM_AXES_WINDLOOM, WINDLOOM_OUTSIDE_CLAMP) ||
        !strstr(windloom_last_error(), "/no/such/bake")) {
        fprintf(stderr, "a missing folder: no error naming it (%s)\n", windloom_last_error());
        return 1;
    }
    WindloomWind *w = windloom_open(folder, WINDLOOM_AXES_WINDLOOM, WINDLOOM_OUTSIDE_CLAMP);
    WindloomWind *unity = windloom_open(folder, WINDLOOM_AXES_UNITY, WINDLOOM_OUTSIDE_CLAMP);
    WindloomWind *unreal = windloom_open(folder, WINDLOOM_AXES_UNREAL, WINDLOOM_OUTSIDE_CLAMP);
    if (!w || !unity || !unreal) {
        fprintf(stderr, "windloom_open: %s\n", windloom_last_error());
        return 1;
    }
    WindloomInfo info;
    if (windloom_info(w, &info) != 0) {
        fprintf(stderr, "windloom_info failed\n");
        return 1;
    }
    size_t nx = info.grid[0], ny = info.grid[1], frames = info.frames;
    size_t cells = nx * ny;

    char path[4096];
    snprintf(path, sizeof path, "%s/wind.f32", folder);
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "%s: cannot open\n", path);
        return 1;
    }
    float *raw = malloc(frames * cells * 2 * sizeof(float));
    size_t read = fread(raw, sizeof(float), frames * cells * 2, f);
    int extra = fgetc(f);
    fclose(f);
    if (read != frames * cells * 2 || extra != EOF) {
        fprintf(stderr, "%s: not %zu frames of %zu x %zu cells\n", path, frames, nx, ny);
        return 1;
    }

    float cx = (info.max[0] - info.min[0]) / (float)nx;
    float cz = (info.max[1] - info.min[1]) / (float)ny;
    float *at = malloc(cells * 3 * sizeof(float));
    float *many = malloc(cells * 3 * sizeof(float));
    size_t checked = 0;
    for (size_t k = 0; k < frames; k++) {
        double t = (double)k / info.fps;
        for (size_t j = 0; j < ny; j++) {
            for (size_t i = 0; i < nx; i++) {
                size_t c = j * nx + i;
                at[3 * c] = info.min[0] + ((float)i + 0.5f) * cx;
                at[3 * c + 1] = y;
                at[3 * c + 2] = info.min[1] + ((float)j + 0.5f) * cz;
            }
        }
        if (windloom_wind_at_many(w, at, cells, t, many) != 0) {
            fprintf(stderr, "windloom_wind_at_many failed\n");
            return 1;
        }
        for (size_t c = 0; c < cells; c++) {
            float vx = raw[(k * cells + c) * 2], vz = raw[(k * cells + c) * 2 + 1];
            float x = at[3 * c], z = at[3 * c + 2], one[3], u[3], e[3];
            windloom_wind_at(w, x, y, z, t, one);
            windloom_wind_at(unity, x, y, -z, t, u);
            windloom_wind_at(unreal, x * 100.0f, z * 100.0f, y * 100.0f, t, e);
            expect(near(one[0], vx) && one[1] == 0.0f && near(one[2], vz), "wind_at (x)", one[0], vx);
            expect(many[3 * c] == one[0] && many[3 * c + 1] == one[1] &&
                       many[3 * c + 2] == one[2],
                   "wind_at_many against wind_at", many[3 * c], one[0]);
            expect(near(u[0], vx) && near(u[2], -vz), "Unity axes (z)", u[2], -vz);
            /* cm/s: within the same rounding in m/s. */
            expect(near(e[0] / 100.0f, vx) && near(e[1] / 100.0f, vz) && e[2] == 0.0f,
                   "Unreal axes (x, cm/s)", e[0], vx * 100.0f);
            checked++;
        }
    }
    /* Nothing was baked meanwhile. */
    if (windloom_reload(w) != 0) {
        fprintf(stderr, "windloom_reload: a new bake where none landed (%s)\n",
                windloom_last_error());
        return 1;
    }
    printf("checked %zu cells of %zu frames (%zu x %zu), sequence %llu\n", checked,
           (size_t)frames, nx, ny, (unsigned long long)info.sequence);
    windloom_close(w);
    windloom_close(unity);
    windloom_close(unreal);
    free(raw);
    free(at);
    free(many);
    return failures ? 1 : 0;
}
