/* capi/mimetic_c.h: mimetic's C ABI (docs/embedding.md), for engines that bind C (native
 * plugins, GDExtension, Rust FFI, ...). Installed as <mimetic/capi/mimetic_c.h>; link the CMake
 * target mimetic::capi (a static library over the runtime libraries, C++ standard library
 * only, so link as C++ or add the C++ runtime).
 *
 * What crosses it: opaque handles, fixed-width integers, floats, NUL-terminated UTF-8
 * strings and caller-owned buffers. No C++ type, no exception: every call catches at the
 * boundary and returns a status.
 *
 * Errors: every function that can fail returns a mimetic_status; MIMETIC_OK is 0. On failure
 * the outputs are left untouched (an output handle is set to NULL) and mimetic_last_error()
 * returns a message naming what is wrong and where ("mimetic_evaluate: positions holds 30
 * floats; the rig's 121 vertices need 363").
 *
 * Lifetimes: a rig and a clip are immutable once loaded and may be used from any number of
 * threads at once; a context holds one character's per-frame state and must be used by one
 * thread at a time (one context per character per thread). A context refers to its rig: destroy
 * every context of a rig before the rig. Destroying NULL does nothing.
 *
 * Per frame (mimetic_clip_sample, mimetic_evaluate, mimetic_play) nothing is allocated and
 * the results are deterministic: the same inputs give the same bits, as the C++ EvaluateJob
 * and ClipSampleJob give them. */
#ifndef MIMETIC_C_H_
#define MIMETIC_C_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version of this interface: raised when a declaration changes. */
#define MIMETIC_C_API_VERSION 2  /* 2: mimetic_evaluate_ex, the scheduler hook, tension */

typedef enum mimetic_status {
  MIMETIC_OK = 0,
  MIMETIC_ERROR_INVALID_ARGUMENT = 1, /* a NULL or misaligned pointer, a bad index or option */
  MIMETIC_ERROR_IO = 2,               /* a file that cannot be opened or read */
  MIMETIC_ERROR_FORMAT = 3,           /* bytes that are not a valid .mrig / .mclip */
  MIMETIC_ERROR_BUFFER_TOO_SMALL = 4, /* a caller buffer shorter than the result */
  MIMETIC_ERROR_MISMATCH = 5,         /* a clip or activations for another muscle count */
  MIMETIC_ERROR_OUT_OF_MEMORY = 6,
  MIMETIC_ERROR_INTERNAL = 7          /* a bug: please report it with the message */
} mimetic_status;

typedef struct mimetic_rig mimetic_rig;         /* a compiled rig (.mrig), immutable */
typedef struct mimetic_clip mimetic_clip;       /* a compiled clip (.mclip), immutable */
typedef struct mimetic_context mimetic_context; /* one character's evaluation state */

typedef struct mimetic_rig_info {
  uint32_t vertex_count;   /* positions and normals are 3 floats per vertex */
  uint32_t triangle_count; /* the triangle indices are 3 per triangle, into the vertices */
  uint32_t muscle_count;   /* activations are 1 float per muscle, in rig order */
  uint32_t has_jaw;        /* 1 when the rig has a jaw (the `jaw` argument moves it), else 0 */
  uint32_t tension_region_count; /* named tension regions (docs/tension.md); 0: none */
} mimetic_rig_info;

typedef struct mimetic_clip_info {
  float duration;          /* seconds */
  uint32_t loops;          /* 1: time wraps into [0, duration); 0: it is clamped */
  uint32_t channel_count;
  uint32_t muscle_count;   /* the rig's it was compiled for: mimetic_clip_sample writes these */
  uint32_t animates_jaw;   /* 1 when the clip sets the jaw */
} mimetic_clip_info;

/* MIMETIC_C_API_VERSION of the library linked (a header/library mismatch check). */
uint32_t mimetic_api_version(void);

/* The message of the most recent failing call on the calling thread; "" before any. Never NULL.
 * Each thread has its own; the pointer stays valid until the next failing call on the same
 * thread (copy it to keep it). Successful calls do not change it. */
const char* mimetic_last_error(void);

/* A short name of a status ("MIMETIC_ERROR_IO"); "unknown status" for other values. Static. */
const char* mimetic_status_name(mimetic_status status);

/* ---- rigs ---------------------------------------------------------------------------- */

/* Loads a compiled rig (`mimetic build RIG --out FILE.mrig`, docs/mrig-format.md) from a file
 * or from `size` bytes at `bytes` (copied: the caller may free them after the call). Every
 * size, checksum and index is checked: a truncated, corrupt or hostile file is
 * MIMETIC_ERROR_FORMAT with the section named. *out is NULL on failure. */
mimetic_status mimetic_rig_load_file(const char* path, mimetic_rig** out);
mimetic_status mimetic_rig_load_memory(const void* bytes, size_t size, mimetic_rig** out);
void mimetic_rig_destroy(mimetic_rig* rig);

mimetic_status mimetic_rig_get_info(const mimetic_rig* rig, mimetic_rig_info* out);

/* The name of muscle `index` (< muscle_count), NUL-terminated UTF-8, owned by the rig (valid
 * until the rig is destroyed). */
mimetic_status mimetic_rig_muscle_name(const mimetic_rig* rig, uint32_t index, const char** out);

/* The triangles' vertex indices (3 per triangle, counter-clockwise seen from outside) into
 * out[0, 3 * triangle_count); `capacity` is out's length in uint32_t. */
mimetic_status mimetic_rig_triangles(const mimetic_rig* rig, uint32_t* out, size_t capacity);

/* The name of tension region `index` (< tension_region_count; docs/tension.md), owned by the
 * rig: the order of mimetic_evaluate_options.region_weights. */
mimetic_status mimetic_rig_tension_region_name(const mimetic_rig* rig, uint32_t index,
                                               const char** out);

/* ---- contexts -------------------------------------------------------------------------- */

/* A context for `rig` (allocates the per-frame state once; any number per rig). */
mimetic_status mimetic_context_create(const mimetic_rig* rig, mimetic_context** out);
void mimetic_context_destroy(mimetic_context* context);

/* Evaluates the rig at `activations` (activation_count == muscle_count floats, rig order;
 * clamped to [0, 1], NaN as 0) and `jaw` (the jaw opening, [0, 1]; ignored by a rig without a
 * jaw) with every skin layer the rig has. Writes 3 floats (x, y, z) per vertex into
 * positions[0, 3 * vertex_count) and, when `normals` is not NULL, unit normals into
 * normals[0, 3 * vertex_count); the capacities are the buffers' lengths in floats. */
mimetic_status mimetic_evaluate(mimetic_context* context, const float* activations,
                                size_t activation_count, float jaw, float* positions,
                                size_t positions_capacity, float* normals,
                                size_t normals_capacity);

/* The skin layers (docs/model.md §4-8), for mimetic_evaluate_options.layers; a layer the rig
 * does not have is skipped either way. */
#define MIMETIC_LAYER_THICKNESS 1u
#define MIMETIC_LAYER_MUSCLE_WRINKLES 2u
#define MIMETIC_LAYER_CURVE_WRINKLES 4u
#define MIMETIC_LAYERS_ALL 7u

/* What mimetic_evaluate_ex does beyond mimetic_evaluate. Fill it with
 * mimetic_evaluate_options_init (which sets `size`, so that a later, longer version of this
 * struct stays compatible), then set what you need. Strides are in bytes between consecutive
 * vertices (a multiple of 4; 0: packed), so the outputs can go straight into an interleaved
 * vertex buffer; a buffer's capacity (in floats) must then reach its last vertex's last float. */
typedef struct mimetic_evaluate_options {
  uint32_t size;             /* sizeof(mimetic_evaluate_options) */
  uint32_t layers;           /* MIMETIC_LAYER_* bits; MIMETIC_LAYERS_ALL by default */
  uint32_t positions_stride; /* >= 12 or 0 (12) */
  uint32_t normals_stride;   /* >= 12 or 0 (12) */
  /* Tension for engine shaders (docs/tension.md), both optional (NULL: not computed): per
   * vertex the area ratio r and the compression eps (2 floats at tension_stride, >= 8 or 0
   * (8)); per tension region its weight in [0, 1] (region_weights_capacity >= the rig's
   * tension_region_count). */
  float* tension;
  size_t tension_capacity;
  uint32_t tension_stride;
  float* region_weights;
  size_t region_weights_capacity;
} mimetic_evaluate_options;

/* Defaults: every layer, packed outputs, no tension. */
void mimetic_evaluate_options_init(mimetic_evaluate_options* options);

/* mimetic_evaluate with `options` (NULL: the defaults, the same as mimetic_evaluate). A wrong
 * `size`, an unknown layer bit, a stride below its minimum (12 bytes for positions and
 * normals, 8 for tension) or not a multiple of 4, or a buffer pointer not aligned to 4 bytes is
 * MIMETIC_ERROR_INVALID_ARGUMENT; a buffer too short for its stride
 * MIMETIC_ERROR_BUFFER_TOO_SMALL. Each message names the argument and the values. */
mimetic_status mimetic_evaluate_ex(mimetic_context* context, const float* activations,
                                   size_t activation_count, float jaw,
                                   const mimetic_evaluate_options* options, float* positions,
                                   size_t positions_capacity, float* normals,
                                   size_t normals_capacity);

/* An engine's scheduler (docs/embedding.md "Threads"): parallel_for(user, count, task,
 * task_data) must call task(task_data, begin, end) over disjoint ranges that together cover
 * [0, count), on any threads, and return when every call has returned. */
typedef void (*mimetic_task_fn)(void* task_data, uint32_t begin, uint32_t end);
typedef void (*mimetic_parallel_for_fn)(void* user, uint32_t count, mimetic_task_fn task,
                                        void* task_data);

/* Gives the context's evaluations (mimetic_evaluate, _ex, mimetic_play) to `parallel_for`
 * (NULL: the calling thread only, the default). Loops over fewer than `min_count` items stay on
 * the calling thread (0: the library's default, 4096). Any split gives the same bits. */
mimetic_status mimetic_context_set_parallel_for(mimetic_context* context,
                                                mimetic_parallel_for_fn parallel_for,
                                                void* user, uint32_t min_count);

/* ---- clips ----------------------------------------------------------------------------- */

/* Loads a compiled clip (`mimetic build CLIP --rig RIG --out FILE.mclip`,
 * docs/mclip-format.md) from a file or from memory (copied). Checked like a rig. */
mimetic_status mimetic_clip_load_file(const char* path, mimetic_clip** out);
mimetic_status mimetic_clip_load_memory(const void* bytes, size_t size, mimetic_clip** out);
void mimetic_clip_destroy(mimetic_clip* clip);

mimetic_status mimetic_clip_get_info(const mimetic_clip* clip, mimetic_clip_info* out);

/* MIMETIC_OK when `clip` was compiled for a rig of `rig`'s muscle count, else
 * MIMETIC_ERROR_MISMATCH naming both counts. (Only the count can be checked: compile each clip
 * for the rig it plays on.) */
mimetic_status mimetic_clip_check_rig(const mimetic_clip* clip, const mimetic_rig* rig);

/* Samples the clip at `time` seconds (any value; the clip's end rule applies, NaN as 0) into
 * activations[0, muscle_count) (capacity: its length in floats) and, when `jaw` is not NULL,
 * the jaw opening into *jaw (0 when the clip does not animate it). */
mimetic_status mimetic_clip_sample(const mimetic_clip* clip, float time, float* activations,
                                   size_t capacity, float* jaw);

/* mimetic_clip_sample into the context's own activations, then mimetic_evaluate: one frame of
 * one character. MIMETIC_ERROR_MISMATCH when the clip is for another muscle count. */
mimetic_status mimetic_play(mimetic_context* context, const mimetic_clip* clip, float time,
                            float* positions, size_t positions_capacity, float* normals,
                            size_t normals_capacity);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* MIMETIC_C_H_ */
