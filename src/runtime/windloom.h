/* windloom runtime: the wind of a windloom bake, for any engine that can call C.
 *
 * Link the runtime library (libwindloom_runtime.so / .dylib, windloom_runtime.dll, or the
 * static library) built from src/runtime (cargo build --release -p windloom-runtime), open
 * a bake folder, and ask for the wind anywhere at any time. docs/RUNTIME.md has the axes,
 * units, costs and each engine's few lines.
 *
 * Threads: queries (windloom_wind_at, windloom_wind_at_many, windloom_info) may run on any
 * number of threads at once; windloom_reload and windloom_close must not run while another
 * call uses the same handle. windloom_last_error is per thread. */
#ifndef WINDLOOM_H
#define WINDLOOM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The axes and units positions are given and winds returned in. */
enum {
    WINDLOOM_AXES_WINDLOOM = 0, /* x east, y up, z south; m, m/s. Godot and Bevy as they are. */
    WINDLOOM_AXES_UNITY = 1,    /* X = x, Y = up, Z = north; m, m/s. */
    WINDLOOM_AXES_UNREAL = 2    /* X = x, Y = south, Z = up; cm, cm/s. */
};

/* The wind beyond the baked rectangle. */
enum {
    WINDLOOM_OUTSIDE_CLAMP = 0, /* the wind at the nearest edge (a texture's Clamp) */
    WINDLOOM_OUTSIDE_ZERO = 1,  /* no wind */
    WINDLOOM_OUTSIDE_WRAP = 2   /* the bake repeats (periodic levels) */
};

typedef struct WindloomWind WindloomWind;

typedef struct WindloomInfo {
    uint64_t sequence;   /* one more with every bake into the folder */
    uint32_t grid[2];    /* cells along x and z */
    float min[2];        /* the baked rectangle, windloom's x and z, metres */
    float max[2];
    uint32_t frames;
    float fps;
    uint32_t looped;     /* 1: time wraps past the last frame */
    float duration;      /* seconds the frames span */
    float max_speed;     /* m/s */
    uint64_t memory_bytes;
} WindloomInfo;

/* Opens the bake in folder (UTF-8). NULL on failure: windloom_last_error() says why. */
WindloomWind *windloom_open(const char *folder, uint32_t axes, uint32_t outside);

/* Why this thread's last call failed, or "". Valid until this thread's next call. */
const char *windloom_last_error(void);

/* The wind at (x, y, z) at t seconds into out[0..3]. 0, or -1 for a NULL pointer.
 * t is the game's clock as a double: no need to wrap it, a clock a month on reads the wind
 * as precisely as one just started. */
int32_t windloom_wind_at(const WindloomWind *wind, float x, float y, float z, double t,
                         float out[3]);

/* The wind at count positions (xyz, xyz, ...) at t seconds into out (3 floats each).
 * 0, or -1 for a NULL pointer or a count no array can hold. */
int32_t windloom_wind_at_many(const WindloomWind *wind, const float *positions, size_t count,
                              double t, float *out);

/* Looks for a new bake: 1 a new bake answers, 0 nothing changed, -1 it could not be read
 * (windloom_last_error says why; the last good bake goes on answering). */
int32_t windloom_reload(WindloomWind *wind);

/* What the answering bake holds. 0, or -1 for a NULL pointer. */
int32_t windloom_info(const WindloomWind *wind, WindloomInfo *out);

/* Closes a handle; NULL is ignored. */
void windloom_close(WindloomWind *wind);

#ifdef __cplusplus
}
#endif

#endif
