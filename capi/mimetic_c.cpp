// capi/mimetic_c.cpp: the C ABI (capi/mimetic_c.h) over the runtime: Rig + ReadRigBinary,
// CompiledClip + ReadClipBinary, EvaluateContext + EvaluateJob, ClipSampleJob. Every entry
// point runs its body inside Guard, which turns any exception into a status and a message, so
// nothing C++ crosses the boundary.
#include "capi/mimetic_c.h"

#include <cstdint>
#include <new>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/binary_sections.h"
#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/rig_binary.h"

struct mimetic_rig {
  mimetic::Rig rig;
};

struct mimetic_clip {
  mimetic::CompiledClip clip;
};

struct mimetic_context {
  const mimetic_rig* rig = nullptr;
  mimetic::EvaluateContext evaluate;
  std::vector<float> activations;  // mimetic_play's: one per muscle
  // mimetic_context_set_parallel_for's scheduler (the C type is the runtime's ParallelForFn).
  mimetic::ParallelForFn parallel_for = nullptr;
  void* parallel_for_user = nullptr;
  uint32_t parallel_min_count = mimetic::kParallelMinCount;
};

static_assert(std::is_same_v<mimetic_parallel_for_fn, mimetic::ParallelForFn>,
              "the C scheduler type is the runtime's");

namespace {

thread_local std::string g_last_error;

mimetic_status Fail(mimetic_status status, std::string message) {
  g_last_error = std::move(message);
  return status;
}

// Runs `body` (returning a status); an exception becomes a status and a message. Each entry
// point names itself in `fn` first: inside the lambda, __func__ would be "operator()".
template <class F>
mimetic_status Guard(const char* function, F&& body) noexcept {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    try {
      return Fail(MIMETIC_ERROR_OUT_OF_MEMORY, std::string(function) + ": out of memory");
    } catch (...) {
      return MIMETIC_ERROR_OUT_OF_MEMORY;
    }
  } catch (...) {
    try {
      return Fail(MIMETIC_ERROR_INTERNAL, std::string(function) + ": unexpected C++ exception");
    } catch (...) {
      return MIMETIC_ERROR_INTERNAL;
    }
  }
}

std::string Null(const char* function, const char* argument) {
  return std::string(function) + ": " + argument + " is NULL";
}

std::string N(uint64_t v) { return std::to_string(v); }

// Every buffer crossing the ABI holds 4-byte elements (float, uint32_t): a pointer must be a
// multiple of 4 (C and C++ make any other access undefined; some CPUs fault on it).
bool Aligned(const void* p) { return reinterpret_cast<uintptr_t>(p) % 4 == 0; }

std::string Misaligned(const char* function, const char* argument, const void* p) {
  return std::string(function) + ": " + argument + " (address " +
         N(reinterpret_cast<uintptr_t>(p)) + ") is not a multiple of 4 bytes; a float or "
         "uint32_t buffer must be aligned to 4";
}

mimetic::span<const uint8_t> Bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// Floats a strided buffer of `count` vertices of `width` floats needs (0 for no vertex).
size_t Needed(size_t count, size_t stride_bytes, size_t width) {
  return count ? (count - 1) * (stride_bytes / 4) + width : 0;
}

// The checks every evaluation shares (the capacities in floats), then EvaluateJob with
// `options` (null: the defaults).
mimetic_status Evaluate(const char* function, mimetic_context* c, const float* activations,
                        float jaw, const mimetic_evaluate_options* options, float* positions,
                        size_t positions_capacity, float* normals, size_t normals_capacity) {
  if (!c) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(function, "context"));
  if (!positions) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(function, "positions"));
  mimetic_evaluate_options o;
  mimetic_evaluate_options_init(&o);
  if (options) {
    if (options->size != sizeof(mimetic_evaluate_options))
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT,
                  std::string(function) + ": options->size is " + N(options->size) +
                      "; expected sizeof(mimetic_evaluate_options) = " +
                      N(sizeof(mimetic_evaluate_options)) +
                      " (fill it with mimetic_evaluate_options_init)");
    o = *options;
  }
  if (o.layers & ~MIMETIC_LAYERS_ALL)
    return Fail(MIMETIC_ERROR_INVALID_ARGUMENT,
                std::string(function) + ": options->layers has unknown bits (" + N(o.layers) +
                    "); expected MIMETIC_LAYER_* bits, at most " + N(MIMETIC_LAYERS_ALL));
  struct Stride {
    const char* name;
    uint32_t* value;
    uint32_t min;
  } strides[] = {{"positions_stride", &o.positions_stride, 12},
                 {"normals_stride", &o.normals_stride, 12},
                 {"tension_stride", &o.tension_stride, 8}};
  for (Stride& st : strides) {
    if (*st.value == 0) *st.value = st.min;
    if (*st.value < st.min || *st.value % 4)
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT,
                  std::string(function) + ": options->" + st.name + " is " + N(*st.value) +
                      " bytes; expected 0 or a multiple of 4 of at least " + N(st.min));
  }
  const mimetic::Rig& rig = c->rig->rig;
  const size_t nv = rig.vertex_count(), nr = rig.tension_region_count();
  struct Buffer {
    const char* name;
    const float* data;
    size_t capacity, need;
  } buffers[] = {
      {"positions", positions, positions_capacity, Needed(nv, o.positions_stride, 3)},
      {"normals", normals, normals_capacity, Needed(nv, o.normals_stride, 3)},
      {"options->tension", o.tension, o.tension_capacity, Needed(nv, o.tension_stride, 2)},
      {"options->region_weights", o.region_weights, o.region_weights_capacity, nr},
  };
  for (const Buffer& b : buffers)
    if (!Aligned(b.data))
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Misaligned(function, b.name, b.data));
  for (const Buffer& b : buffers)
    if (b.data && b.capacity < b.need)
      return Fail(MIMETIC_ERROR_BUFFER_TOO_SMALL,
                  std::string(function) + ": " + b.name + " holds " + N(b.capacity) +
                      " floats; the rig's " +
                      (b.need == nr && b.data == o.region_weights
                           ? N(nr) + " tension regions need " + N(b.need)
                           : N(nv) + " vertices need " + N(b.need)));
  mimetic::EvaluateJob job;
  job.rig = &rig;
  job.context = &c->evaluate;
  job.activations = mimetic::span<const float>(activations, rig.muscle_count());
  job.jaw = jaw;
  job.layers = {.thickness = (o.layers & MIMETIC_LAYER_THICKNESS) != 0,
                .muscle_wrinkles = (o.layers & MIMETIC_LAYER_MUSCLE_WRINKLES) != 0,
                .curve_wrinkles = (o.layers & MIMETIC_LAYER_CURVE_WRINKLES) != 0};
  job.out_positions = mimetic::span<float>(positions, buffers[0].need);
  job.out_positions_stride = o.positions_stride;
  if (normals) {
    job.out_normals = mimetic::span<float>(normals, buffers[1].need);
    job.out_normals_stride = o.normals_stride;
  }
  if (o.tension) {
    job.out_tension = mimetic::span<float>(o.tension, buffers[2].need);
    job.out_tension_stride = o.tension_stride;
  }
  if (o.region_weights) job.out_region_weights = mimetic::span<float>(o.region_weights, nr);
  job.parallel_for = c->parallel_for;
  job.parallel_for_user = c->parallel_for_user;
  job.parallel_min_count = c->parallel_min_count;
  if (!job.Run())
    return Fail(MIMETIC_ERROR_INTERNAL,
                std::string(function) + ": EvaluateJob refused the job after the C checks");
  return MIMETIC_OK;
}

}  // namespace

extern "C" {

uint32_t mimetic_api_version(void) { return MIMETIC_C_API_VERSION; }

const char* mimetic_last_error(void) { return g_last_error.c_str(); }

const char* mimetic_status_name(mimetic_status status) {
  switch (status) {
    case MIMETIC_OK: return "MIMETIC_OK";
    case MIMETIC_ERROR_INVALID_ARGUMENT: return "MIMETIC_ERROR_INVALID_ARGUMENT";
    case MIMETIC_ERROR_IO: return "MIMETIC_ERROR_IO";
    case MIMETIC_ERROR_FORMAT: return "MIMETIC_ERROR_FORMAT";
    case MIMETIC_ERROR_BUFFER_TOO_SMALL: return "MIMETIC_ERROR_BUFFER_TOO_SMALL";
    case MIMETIC_ERROR_MISMATCH: return "MIMETIC_ERROR_MISMATCH";
    case MIMETIC_ERROR_OUT_OF_MEMORY: return "MIMETIC_ERROR_OUT_OF_MEMORY";
    case MIMETIC_ERROR_INTERNAL: return "MIMETIC_ERROR_INTERNAL";
  }
  return "unknown status";
}

// ---- rigs -------------------------------------------------------------------------------

static mimetic_status LoadRig(const char* function, const std::string* path,
                              mimetic::span<const uint8_t> bytes, mimetic_rig** out) {
  auto rig = new mimetic_rig;
  std::string error;
  if (!mimetic::ReadRigBinary(bytes, &rig->rig, nullptr, &error)) {
    delete rig;
    return Fail(MIMETIC_ERROR_FORMAT,
                std::string(function) + ": " + (path ? *path + ": " : std::string()) + error);
  }
  *out = rig;
  return MIMETIC_OK;
}

mimetic_status mimetic_rig_load_file(const char* path, mimetic_rig** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (out) *out = nullptr;
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (!path) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "path"));
    std::string bytes, error;
    const std::string p = path;
    if (!mimetic::ReadRigBinaryFile(p, &bytes, &error))
      return Fail(MIMETIC_ERROR_IO, std::string(fn) + ": " + p + ": " + error);
    return LoadRig(fn, &p, Bytes(bytes), out);
  });
}

mimetic_status mimetic_rig_load_memory(const void* bytes, size_t size, mimetic_rig** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (out) *out = nullptr;
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (!bytes && size) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "bytes"));
    return LoadRig(fn, nullptr,
                   mimetic::span<const uint8_t>(static_cast<const uint8_t*>(bytes), size), out);
  });
}

void mimetic_rig_destroy(mimetic_rig* rig) { delete rig; }

mimetic_status mimetic_rig_get_info(const mimetic_rig* rig, mimetic_rig_info* out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    out->vertex_count = rig->rig.vertex_count();
    out->triangle_count = rig->rig.triangle_count();
    out->muscle_count = rig->rig.muscle_count();
    out->has_jaw = rig->rig.jaw().empty() ? 0 : 1;
    out->tension_region_count = rig->rig.tension_region_count();
    return MIMETIC_OK;
  });
}

mimetic_status mimetic_rig_muscle_name(const mimetic_rig* rig, uint32_t index, const char** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (index >= rig->rig.muscle_count())
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, std::string(fn) + ": muscle " + N(index) +
                                                      "; the rig has " +
                                                      N(rig->rig.muscle_count()) + " muscles");
    *out = rig->rig.muscle_names()[index].c_str();
    return MIMETIC_OK;
  });
}

mimetic_status mimetic_rig_tension_region_name(const mimetic_rig* rig, uint32_t index,
                                               const char** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    const uint32_t n = rig->rig.tension_region_count();
    if (index >= n)
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, std::string(fn) + ": tension region " +
                                                      N(index) + "; the rig has " + N(n));
    *out = rig->rig.tension_regions().names[index].c_str();
    return MIMETIC_OK;
  });
}

mimetic_status mimetic_rig_triangles(const mimetic_rig* rig, uint32_t* out, size_t capacity) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (!Aligned(out)) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Misaligned(fn, "out", out));
    const std::vector<uint32_t>& idx = rig->rig.vertex_indices();
    if (capacity < idx.size())
      return Fail(MIMETIC_ERROR_BUFFER_TOO_SMALL,
                  std::string(fn) + ": out holds " + N(capacity) + " indices; the rig's " +
                      N(rig->rig.triangle_count()) + " triangles need " + N(idx.size()));
    for (size_t i = 0; i < idx.size(); ++i) out[i] = idx[i];
    return MIMETIC_OK;
  });
}

// ---- contexts ---------------------------------------------------------------------------

mimetic_status mimetic_context_create(const mimetic_rig* rig, mimetic_context** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (out) *out = nullptr;
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    auto c = new mimetic_context;
    try {
      c->rig = rig;
      c->evaluate.Resize(rig->rig);
      c->activations.assign(rig->rig.muscle_count(), 0.f);
    } catch (...) {
      delete c;
      throw;
    }
    *out = c;
    return MIMETIC_OK;
  });
}

void mimetic_context_destroy(mimetic_context* context) { delete context; }

void mimetic_evaluate_options_init(mimetic_evaluate_options* options) {
  if (!options) return;
  *options = mimetic_evaluate_options{};
  options->size = sizeof(mimetic_evaluate_options);
  options->layers = MIMETIC_LAYERS_ALL;
}

// mimetic_evaluate(_ex)'s body, `fn` naming the entry point in messages.
static mimetic_status EvaluateEntry(const char* fn, mimetic_context* context,
                                    const float* activations, size_t activation_count, float jaw,
                                    const mimetic_evaluate_options* options, float* positions,
                                    size_t positions_capacity, float* normals,
                                    size_t normals_capacity) {
  return Guard(fn, [&] {
    if (!context) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "context"));
    const uint32_t muscles = context->rig->rig.muscle_count();
    if (!activations && muscles)
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "activations"));
    if (!Aligned(activations))
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Misaligned(fn, "activations", activations));
    if (activation_count != muscles)
      return Fail(MIMETIC_ERROR_MISMATCH, std::string(fn) + ": " + N(activation_count) +
                                              " activations; the rig has " + N(muscles) +
                                              " muscles");
    return Evaluate(fn, context, activations, jaw, options, positions, positions_capacity,
                    normals, normals_capacity);
  });
}

mimetic_status mimetic_evaluate_ex(mimetic_context* context, const float* activations,
                                   size_t activation_count, float jaw,
                                   const mimetic_evaluate_options* options, float* positions,
                                   size_t positions_capacity, float* normals,
                                   size_t normals_capacity) {
  return EvaluateEntry(__func__, context, activations, activation_count, jaw, options, positions,
                       positions_capacity, normals, normals_capacity);
}

mimetic_status mimetic_evaluate(mimetic_context* context, const float* activations,
                                size_t activation_count, float jaw, float* positions,
                                size_t positions_capacity, float* normals,
                                size_t normals_capacity) {
  return EvaluateEntry(__func__, context, activations, activation_count, jaw, nullptr, positions,
                       positions_capacity, normals, normals_capacity);
}

mimetic_status mimetic_context_set_parallel_for(mimetic_context* context,
                                                mimetic_parallel_for_fn parallel_for,
                                                void* user, uint32_t min_count) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!context) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "context"));
    context->parallel_for = parallel_for;
    context->parallel_for_user = user;
    context->parallel_min_count = min_count ? min_count : mimetic::kParallelMinCount;
    return MIMETIC_OK;
  });
}

// ---- clips ------------------------------------------------------------------------------

static mimetic_status LoadClip(const char* function, const std::string* path,
                               mimetic::span<const uint8_t> bytes, mimetic_clip** out) {
  auto clip = new mimetic_clip;
  std::string error;
  if (!mimetic::ReadClipBinary(bytes, &clip->clip, &error)) {
    delete clip;
    return Fail(MIMETIC_ERROR_FORMAT,
                std::string(function) + ": " + (path ? *path + ": " : std::string()) + error);
  }
  *out = clip;
  return MIMETIC_OK;
}

mimetic_status mimetic_clip_load_file(const char* path, mimetic_clip** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (out) *out = nullptr;
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (!path) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "path"));
    std::string bytes, error;
    const std::string p = path;
    if (!mimetic::binary::ReadFileBytes(p, "compiled clip", mimetic::kMaxClipBinaryFileBytes,
                                        &bytes, &error))
      return Fail(MIMETIC_ERROR_IO, std::string(fn) + ": " + p + ": " + error);
    return LoadClip(fn, &p, Bytes(bytes), out);
  });
}

mimetic_status mimetic_clip_load_memory(const void* bytes, size_t size, mimetic_clip** out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (out) *out = nullptr;
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    if (!bytes && size) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "bytes"));
    return LoadClip(fn, nullptr,
                    mimetic::span<const uint8_t>(static_cast<const uint8_t*>(bytes), size), out);
  });
}

void mimetic_clip_destroy(mimetic_clip* clip) { delete clip; }

mimetic_status mimetic_clip_get_info(const mimetic_clip* clip, mimetic_clip_info* out) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!clip) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "clip"));
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
    const mimetic::CompiledClip& c = clip->clip;
    out->duration = c.duration();
    out->loops = c.end() == mimetic::ClipEnd::kLoop ? 1 : 0;
    out->channel_count = c.channel_count();
    out->muscle_count = c.muscle_count();
    out->animates_jaw = c.animates_jaw() ? 1 : 0;
    return MIMETIC_OK;
  });
}

static mimetic_status CheckClipRig(const char* function, const mimetic_clip* clip,
                                   const mimetic_rig* rig) {
  if (clip->clip.muscle_count() != rig->rig.muscle_count())
    return Fail(MIMETIC_ERROR_MISMATCH,
                std::string(function) + ": the clip \"" + clip->clip.name() +
                    "\" was compiled for a rig of " + N(clip->clip.muscle_count()) +
                    " muscles; this rig has " + N(rig->rig.muscle_count()) +
                    " (compile the clip for this rig: mimetic build CLIP --rig RIG)");
  return MIMETIC_OK;
}

mimetic_status mimetic_clip_check_rig(const mimetic_clip* clip, const mimetic_rig* rig) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!clip) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "clip"));
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    return CheckClipRig(fn, clip, rig);
  });
}

mimetic_status mimetic_clip_sample(const mimetic_clip* clip, float time, float* activations,
                                   size_t capacity, float* jaw) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!clip) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "clip"));
    const uint32_t muscles = clip->clip.muscle_count();
    if (!activations && muscles)
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "activations"));
    if (!Aligned(activations))
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Misaligned(fn, "activations", activations));
    if (!Aligned(jaw)) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Misaligned(fn, "jaw", jaw));
    if (capacity < muscles)
      return Fail(MIMETIC_ERROR_BUFFER_TOO_SMALL,
                  std::string(fn) + ": activations holds " + N(capacity) +
                      " floats; the clip's " + N(muscles) + " muscles need " + N(muscles));
    mimetic::ClipSampleJob job;
    job.clip = &clip->clip;
    job.time = time;
    job.out_activations = mimetic::span<float>(activations, muscles);
    if (jaw) job.out_jaw = mimetic::span<float>(jaw, 1);
    if (!job.Run())
      return Fail(MIMETIC_ERROR_INTERNAL,
                  std::string(fn) + ": ClipSampleJob refused the job after the C checks");
    return MIMETIC_OK;
  });
}

mimetic_status mimetic_play(mimetic_context* context, const mimetic_clip* clip, float time,
                            float* positions, size_t positions_capacity, float* normals,
                            size_t normals_capacity) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!clip) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "clip"));
    if (!context) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "context"));
    if (!positions) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "positions"));
    const mimetic_status m = CheckClipRig(fn, clip, context->rig);
    if (m != MIMETIC_OK) return m;
    float jaw = 0.f;
    mimetic::ClipSampleJob job;
    job.clip = &clip->clip;
    job.time = time;
    job.out_activations = context->activations;
    job.out_jaw = mimetic::span<float>(&jaw, 1);
    if (!job.Run())
      return Fail(MIMETIC_ERROR_INTERNAL,
                  std::string(fn) + ": ClipSampleJob refused the job after the C checks");
    return Evaluate(fn, context, context->activations.data(), jaw, nullptr, positions,
                    positions_capacity, normals, normals_capacity);
  });
}

}  // extern "C"
