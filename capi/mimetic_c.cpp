// capi/mimetic_c.cpp: the C ABI (capi/mimetic_c.h) over the runtime: Rig + ReadRigBinary,
// CompiledClip + ReadClipBinary, EvaluateContext + EvaluateJob, ClipSampleJob. Every entry
// point runs its body inside Guard, which turns any exception into a status and a message, so
// nothing C++ crosses the boundary.
#include "capi/mimetic_c.h"

#include <cstdint>
#include <new>
#include <string>
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
};

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

mimetic::span<const uint8_t> Bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

// The checks every evaluation shares; the sizes in floats.
mimetic_status CheckOutputs(const char* function, const mimetic_context* c, const float* positions,
                            size_t positions_capacity, const float* normals,
                            size_t normals_capacity) {
  if (!c) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(function, "context"));
  if (!positions) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(function, "positions"));
  const size_t need = 3 * size_t(c->rig->rig.vertex_count());
  if (positions_capacity < need)
    return Fail(MIMETIC_ERROR_BUFFER_TOO_SMALL,
                std::string(function) + ": positions holds " + N(positions_capacity) +
                    " floats; the rig's " + N(c->rig->rig.vertex_count()) + " vertices need " +
                    N(need));
  if (normals && normals_capacity < need)
    return Fail(MIMETIC_ERROR_BUFFER_TOO_SMALL,
                std::string(function) + ": normals holds " + N(normals_capacity) +
                    " floats; the rig's " + N(c->rig->rig.vertex_count()) + " vertices need " +
                    N(need));
  return MIMETIC_OK;
}

mimetic_status Evaluate(const char* function, mimetic_context* c, const float* activations,
                        float jaw, float* positions, float* normals) {
  const mimetic::Rig& rig = c->rig->rig;
  const size_t n = 3 * size_t(rig.vertex_count());
  mimetic::EvaluateJob job;
  job.rig = &rig;
  job.context = &c->evaluate;
  job.activations = mimetic::span<const float>(activations, rig.muscle_count());
  job.jaw = jaw;
  job.out_positions = mimetic::span<float>(positions, n);
  if (normals) job.out_normals = mimetic::span<float>(normals, n);
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

mimetic_status mimetic_rig_triangles(const mimetic_rig* rig, uint32_t* out, size_t capacity) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    if (!rig) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "rig"));
    if (!out) return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "out"));
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

mimetic_status mimetic_evaluate(mimetic_context* context, const float* activations,
                                size_t activation_count, float jaw, float* positions,
                                size_t positions_capacity, float* normals,
                                size_t normals_capacity) {
  const char* const fn = __func__;
  return Guard(fn, [&] {
    const mimetic_status s = CheckOutputs(fn, context, positions, positions_capacity,
                                          normals, normals_capacity);
    if (s != MIMETIC_OK) return s;
    const uint32_t muscles = context->rig->rig.muscle_count();
    if (!activations && muscles)
      return Fail(MIMETIC_ERROR_INVALID_ARGUMENT, Null(fn, "activations"));
    if (activation_count != muscles)
      return Fail(MIMETIC_ERROR_MISMATCH, std::string(fn) + ": " + N(activation_count) +
                                              " activations; the rig has " + N(muscles) +
                                              " muscles");
    return Evaluate(fn, context, activations, jaw, positions, normals);
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
    const mimetic_status s = CheckOutputs(fn, context, positions, positions_capacity,
                                          normals, normals_capacity);
    if (s != MIMETIC_OK) return s;
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
    return Evaluate(fn, context, context->activations.data(), jaw, positions, normals);
  });
}

}  // extern "C"
