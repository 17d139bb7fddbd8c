/* tests/capi/capi_test.c: the C ABI (capi/mimetic_c.h) driven from C (compiled as C99; ctest
 * capi.c_abi):  capi_test DIR
 * DIR holds what capi_reference wrote: a .mrig of the test surface, a .mclip on its muscles, a
 * .mclip for another muscle count, and reference.bin, the C++ runtime's activations, positions
 * and normals at 40 times computed from the JSON rig and clip. Checks: the rig's info and
 * triangles are the reference's; sampling and evaluating through the ABI (two contexts on one
 * rig, and mimetic_play) give the reference's bits exactly; bad inputs (a missing file, a
 * truncated or corrupt .mrig, NULL pointers, buffers too small, activations and a clip for
 * another muscle count) return their status with a message. Then mimetic_evaluate_ex: no skin
 * layer, the tension outputs, interleaved strides and an engine scheduler (a C parallel_for
 * calling the task over three ranges in reverse order; then one splitting each loop between
 * the calling thread and a second pthread, into 32-byte vertices of position, normal and
 * tension) against the reference's bits, its bad options (strides too small or not a multiple
 * of 4, misaligned buffer pointers) refused with their messages. */
#define _POSIX_C_SOURCE 200809L /* pthreads under -std=c99 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capi/mimetic_c.h"

static int failures = 0;

#define CHECK(cond)                                                   \
  do {                                                                \
    if (!(cond)) {                                                    \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                     \
    }                                                                 \
  } while (0)

/* A call that must fail with `status` and a message containing `text`. */
#define EXPECT_ERROR(call, status, text)                                              \
  do {                                                                                \
    mimetic_status s_ = (call);                                                       \
    if (s_ != (status) || strstr(mimetic_last_error(), (text)) == NULL) {             \
      fprintf(stderr, "%s:%d: %s: got %s \"%s\"; expected %s with \"%s\"\n", __FILE__, \
              __LINE__, #call, mimetic_status_name(s_), mimetic_last_error(),         \
              mimetic_status_name(status), (text));                                   \
      ++failures;                                                                     \
    }                                                                                 \
  } while (0)

#define EXPECT_OK(call)                                                                   \
  do {                                                                                    \
    mimetic_status s_ = (call);                                                           \
    if (s_ != MIMETIC_OK) {                                                               \
      fprintf(stderr, "%s:%d: %s: %s \"%s\"\n", __FILE__, __LINE__, #call,                 \
              mimetic_status_name(s_), mimetic_last_error());                             \
      ++failures;                                                                         \
    }                                                                                     \
  } while (0)

static char* ReadAll(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  char* data;
  long n;
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  n = ftell(f);
  fseek(f, 0, SEEK_SET);
  data = (char*)malloc(n > 0 ? (size_t)n : 1);
  if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
    free(data);
    data = NULL;
  }
  fclose(f);
  *size = (size_t)n;
  return data;
}

static int WriteAll(const char* path, const char* data, size_t size) {
  FILE* f = fopen(path, "wb");
  int ok = f && fwrite(data, 1, size, f) == size;
  if (f) ok = fclose(f) == 0 && ok;
  return ok;
}

/* A scheduler as an engine would hand one over: here it calls `task` over three ranges, last
 * first (any split and any order must give the same bits), and counts the calls. */
static int scheduler_calls = 0;
static void ReverseThirds(void* user, uint32_t count, mimetic_task_fn task, void* task_data) {
  const uint32_t a = count / 3, b = 2 * (count / 3);
  int* calls = (int*)user;
  task(task_data, b, count);
  task(task_data, a, b);
  task(task_data, 0, a);
  *calls += 1;
}

/* A scheduler on two threads: the calling thread runs [0, count / 2) while a second thread
 * runs [count / 2, count), then it joins. Counts the calls in which both halves were
 * non-empty, and records whether the second thread's half ran on another thread than the
 * caller (pthread_equal), so the test knows the work was really split. */
typedef struct {
  pthread_t caller;
  int calls, split_calls, other_thread, failed;
} TwoThreadsState;
typedef struct {
  mimetic_task_fn task;
  void* task_data;
  uint32_t begin, end;
  TwoThreadsState* state;
} TwoThreadsHalf;
static void* RunHalf(void* arg) {
  TwoThreadsHalf* h = (TwoThreadsHalf*)arg;
  if (!pthread_equal(pthread_self(), h->state->caller)) h->state->other_thread = 1;
  h->task(h->task_data, h->begin, h->end);
  return NULL;
}
static void TwoThreads(void* user, uint32_t count, mimetic_task_fn task, void* task_data) {
  TwoThreadsState* state = (TwoThreadsState*)user;
  TwoThreadsHalf second;
  pthread_t thread;
  const uint32_t half = count / 2;
  state->caller = pthread_self();
  second.task = task;
  second.task_data = task_data;
  second.begin = half;
  second.end = count;
  second.state = state;
  state->calls += 1;
  if (half == 0 || pthread_create(&thread, NULL, RunHalf, &second) != 0) {
    if (half != 0) state->failed = 1;
    task(task_data, 0, count);
    return;
  }
  task(task_data, 0, half);
  pthread_join(thread, NULL);
  state->split_calls += 1;
}

static uint32_t U32(const char* p) {
  uint32_t v;
  memcpy(&v, p, 4);
  return v;
}

int main(int argc, char** argv) {
  char path[4096], other_path[4096], missing[4096], cut_path[4096];
  size_t ref_size = 0, mrig_size = 0, mclip_size = 0;
  char *ref, *mrig, *mclip;
  const char* at;
  uint32_t vertex_count, triangle_count, muscle_count, has_jaw, frames, f;
  mimetic_rig* rig = NULL;
  mimetic_rig* bad_rig = (mimetic_rig*)&failures; /* must be set to NULL on failure */
  mimetic_clip* clip = NULL;
  mimetic_clip* other = NULL;
  mimetic_context* a = NULL;
  mimetic_context* b = NULL;
  mimetic_context* bad_context = (mimetic_context*)&failures; /* set to NULL on failure */
  mimetic_rig_info info;
  mimetic_clip_info clip_info;
  uint32_t* triangles;
  float *act, *pos, *nrm, *pos2, *nrm2;
  float jaw = -1.f;
  const char* name = NULL;
  const char* frame_data[64] = {0}; /* per frame: its positions and normals in reference.bin */
  uint32_t region_count, k;
  mimetic_evaluate_options options;
  float *inter, *tension, *weights;

  if (argc != 2) {
    fprintf(stderr, "usage: capi_test DIR\n");
    return 2;
  }
  CHECK(mimetic_api_version() == MIMETIC_C_API_VERSION);
  CHECK(strcmp(mimetic_last_error(), "") == 0);
  snprintf(path, sizeof path, "%s/reference.bin", argv[1]);
  ref = ReadAll(path, &ref_size);
  snprintf(path, sizeof path, "%s/surface.mrig", argv[1]);
  mrig = ReadAll(path, &mrig_size);
  snprintf(other_path, sizeof other_path, "%s/surface.mclip", argv[1]);
  mclip = ReadAll(other_path, &mclip_size);
  if (!ref || !mrig || !mclip) {
    fprintf(stderr, "capi_test: %s lacks capi_reference's files\n", argv[1]);
    return 1;
  }
  vertex_count = U32(ref);
  triangle_count = U32(ref + 4);
  muscle_count = U32(ref + 8);
  has_jaw = U32(ref + 12);
  frames = U32(ref + 16);
  at = ref + 20;

  /* The rig from a file: its info and triangles. */
  EXPECT_OK(mimetic_rig_load_file(path, &rig));
  if (!rig) return 1;
  EXPECT_OK(mimetic_rig_get_info(rig, &info));
  CHECK(info.vertex_count == vertex_count);
  CHECK(info.triangle_count == triangle_count);
  CHECK(info.muscle_count == muscle_count);
  CHECK(info.has_jaw == has_jaw);
  EXPECT_OK(mimetic_rig_muscle_name(rig, 0, &name));
  CHECK(name != NULL && strcmp(name, "zygomatic") == 0);
  triangles = (uint32_t*)malloc(3 * sizeof(uint32_t) * triangle_count);
  EXPECT_OK(mimetic_rig_triangles(rig, triangles, 3 * (size_t)triangle_count));
  CHECK(memcmp(triangles, at, 3 * sizeof(uint32_t) * triangle_count) == 0);
  at += 3 * sizeof(uint32_t) * triangle_count;

  /* The clip from memory; two contexts on the one rig. */
  EXPECT_OK(mimetic_clip_load_memory(mclip, mclip_size, &clip));
  if (!clip) return 1;
  EXPECT_OK(mimetic_clip_get_info(clip, &clip_info));
  CHECK(clip_info.muscle_count == muscle_count);
  CHECK(clip_info.loops == 1);
  CHECK(clip_info.channel_count == 3);
  CHECK(clip_info.duration == 2.2f);
  CHECK(clip_info.animates_jaw == 0);
  EXPECT_OK(mimetic_clip_check_rig(clip, rig));
  EXPECT_OK(mimetic_context_create(rig, &a));
  EXPECT_OK(mimetic_context_create(rig, &b));
  if (!a || !b) return 1;

  act = (float*)malloc(sizeof(float) * (muscle_count + 1));
  pos = (float*)malloc(sizeof(float) * 3 * vertex_count);
  nrm = (float*)malloc(sizeof(float) * 3 * vertex_count);
  pos2 = (float*)malloc(sizeof(float) * 3 * vertex_count);
  nrm2 = (float*)malloc(sizeof(float) * 3 * vertex_count);
  for (f = 0; f < frames; ++f) {
    float time;
    const size_t n = 3 * (size_t)vertex_count;
    memcpy(&time, at, 4);
    at += 4;
    EXPECT_OK(mimetic_clip_sample(clip, time, act, muscle_count, &jaw));
    CHECK(memcmp(act, at, sizeof(float) * muscle_count) == 0);
    CHECK(memcmp(&jaw, at + 4 * muscle_count, 4) == 0);
    at += 4 * (muscle_count + 1);
    /* Context a: evaluate the sampled activations; context b: mimetic_play, every other frame
     * (so that the two contexts hold different frames' state). */
    if (f < 64) frame_data[f] = at;
    EXPECT_OK(mimetic_evaluate(a, act, muscle_count, jaw, pos, n, nrm, n));
    CHECK(memcmp(pos, at, sizeof(float) * n) == 0);
    CHECK(memcmp(nrm, at + 4 * n, sizeof(float) * n) == 0);
    if (f % 2 == 0) {
      EXPECT_OK(mimetic_play(b, clip, time, pos2, n, nrm2, n));
      CHECK(memcmp(pos2, at, sizeof(float) * n) == 0);
      CHECK(memcmp(nrm2, at + 4 * n, sizeof(float) * n) == 0);
    }
    at += 8 * n;
  }
  /* mimetic_evaluate_ex at frames 10, 20, 30: no skin layer; every layer with the tension
   * outputs, positions and normals interleaved (24-byte vertices), tension at a 12-byte stride
   * and the scheduler. */
  region_count = U32(at);
  at += 4;
  CHECK(info.tension_region_count == region_count);
  CHECK(region_count == 2);
  EXPECT_OK(mimetic_rig_tension_region_name(rig, 1, &name));
  CHECK(name != NULL && strcmp(name, "top") == 0);
  inter = (float*)malloc(sizeof(float) * 6 * vertex_count);
  tension = (float*)malloc(sizeof(float) * 3 * vertex_count);
  weights = (float*)malloc(sizeof(float) * (region_count + 1));
  EXPECT_OK(mimetic_context_set_parallel_for(b, ReverseThirds, &scheduler_calls, 1));
  for (k = 0; k < 3; ++k) {
    const size_t n = 3 * (size_t)vertex_count;
    const uint32_t frame = U32(at);
    float time = (float)frame * 0.07f - 0.2f;
    uint32_t v;
    int same = 1;
    at += 4;
    CHECK(frame == 10 * (k + 1));
    EXPECT_OK(mimetic_clip_sample(clip, time, act, muscle_count, &jaw));
    mimetic_evaluate_options_init(&options);
    options.layers = 0;
    EXPECT_OK(mimetic_evaluate_ex(a, act, muscle_count, jaw, &options, pos, n, NULL, 0));
    CHECK(memcmp(pos, at, sizeof(float) * n) == 0);
    at += 4 * n;
    mimetic_evaluate_options_init(&options);
    options.positions_stride = 24;
    options.normals_stride = 24;
    options.tension = tension;
    options.tension_capacity = 3 * (size_t)vertex_count - 1;
    options.tension_stride = 12;
    options.region_weights = weights;
    options.region_weights_capacity = region_count;
    EXPECT_OK(mimetic_evaluate_ex(b, act, muscle_count, jaw, &options, inter, 6 * n / 3 * 1 - 3,
                                  inter + 3, 6 * (size_t)vertex_count - 3));
    for (v = 0; v < vertex_count; ++v) {
      same = same && memcmp(inter + 6 * v, frame_data[frame] + 12 * v, 12) == 0 &&
             memcmp(inter + 6 * v + 3, frame_data[frame] + 4 * n + 12 * v, 12) == 0 &&
             memcmp(tension + 3 * v, at + 8 * v, 8) == 0;
    }
    CHECK(same);
    at += 8 * (size_t)vertex_count;
    CHECK(memcmp(weights, at, sizeof(float) * region_count) == 0);
    at += 4 * region_count;
  }
  CHECK(scheduler_calls > 0);
  CHECK(at == ref + ref_size);
  /* The same frames again on context a with the two-thread scheduler and interleaved
   * 32-byte vertices (position, normal, tension in one buffer), against the reference's bits. */
  {
    TwoThreadsState two;
    const size_t stride = 8, floats = stride * (size_t)vertex_count;
    float* vb = (float*)malloc(sizeof(float) * floats);
    const char* back = at - (size_t)3 * (4 + 4 * 3 * (size_t)vertex_count +
                                         8 * (size_t)vertex_count + 4 * (size_t)region_count);
    memset(&two, 0, sizeof two);
    EXPECT_OK(mimetic_context_set_parallel_for(a, TwoThreads, &two, 1));
    for (k = 0; k < 3; ++k) {
      const size_t n = 3 * (size_t)vertex_count;
      const uint32_t frame = U32(back);
      uint32_t v;
      int same = 1;
      back += 4 + 4 * n; /* the frame, then the no-layer positions */
      CHECK(frame == 10 * (k + 1));
      EXPECT_OK(mimetic_clip_sample(clip, (float)frame * 0.07f - 0.2f, act, muscle_count, &jaw));
      memset(vb, 0xff, sizeof(float) * floats); /* NaNs: every written float is checked */
      mimetic_evaluate_options_init(&options);
      options.positions_stride = options.normals_stride = options.tension_stride =
          (uint32_t)(stride * sizeof(float));
      options.tension = vb + 6;
      options.tension_capacity = floats - 6;
      options.region_weights = weights;
      options.region_weights_capacity = region_count;
      EXPECT_OK(mimetic_evaluate_ex(a, act, muscle_count, jaw, &options, vb, floats, vb + 3,
                                    floats - 3));
      for (v = 0; v < vertex_count; ++v)
        same = same && memcmp(vb + stride * v, frame_data[frame] + 12 * v, 12) == 0 &&
               memcmp(vb + stride * v + 3, frame_data[frame] + 4 * n + 12 * v, 12) == 0 &&
               memcmp(vb + stride * v + 6, back + 8 * v, 8) == 0;
      CHECK(same);
      back += 8 * (size_t)vertex_count;
      CHECK(memcmp(weights, back, sizeof(float) * region_count) == 0);
      back += 4 * region_count;
    }
    CHECK(back == at);
    CHECK(two.failed == 0);
    CHECK(two.split_calls > 0);
    CHECK(two.other_thread == 1);
    printf("capi_test: two-thread scheduler: %d calls, %d split across two threads\n",
           two.calls, two.split_calls);
    EXPECT_OK(mimetic_context_set_parallel_for(a, NULL, NULL, 0));
    free(vb);
  }
  /* Positions alone (normals NULL). */
  EXPECT_OK(mimetic_evaluate(a, act, muscle_count, 0.f, pos, 3 * (size_t)vertex_count, NULL, 0));
  CHECK(!isnan(pos[0]));
  CHECK(strcmp(mimetic_last_error(), "") == 0); /* nothing failed so far */
  /* Bad options. */
  mimetic_evaluate_options_init(&options);
  options.size = 8;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "mimetic_evaluate_ex: options->size is 8");
  mimetic_evaluate_options_init(&options);
  options.layers = 8;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "options->layers has unknown bits");
  mimetic_evaluate_options_init(&options);
  options.positions_stride = 10;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "options->positions_stride is 10 bytes");
  mimetic_evaluate_options_init(&options);
  options.positions_stride = 8; /* a multiple of 4, but less than 3 floats */
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "options->positions_stride is 8 bytes; expected 0 or a multiple of 4 of at least 12");
  mimetic_evaluate_options_init(&options);
  options.positions_stride = 14; /* at least 12, but it would misalign every other vertex */
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "options->positions_stride is 14 bytes");
  mimetic_evaluate_options_init(&options);
  options.normals_stride = 4;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, nrm, 3 * (size_t)vertex_count),
               MIMETIC_ERROR_INVALID_ARGUMENT, "options->normals_stride is 4 bytes");
  mimetic_evaluate_options_init(&options);
  options.tension = tension;
  options.tension_capacity = 3 * (size_t)vertex_count;
  options.tension_stride = 6;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "options->tension_stride is 6 bytes; expected 0 or a multiple of 4 of at least 8");
  /* Misaligned buffers: a float pointer 2 bytes into an allocation (formally undefined to form
   * in C; what an engine passing a packed byte offset would hand over, and never dereferenced
   * here: the library refuses it before any access). */
  {
    char* raw = (char*)malloc(sizeof(float) * (6 * (size_t)vertex_count + 2));
    float* odd = (float*)(void*)(raw + 2);
    mimetic_evaluate_options_init(&options);
    EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, odd, 3 * (size_t)vertex_count, NULL, 0),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "mimetic_evaluate_ex: positions (address");
    EXPECT_ERROR(mimetic_evaluate(a, act, muscle_count, 0.f, pos, 3 * (size_t)vertex_count, odd, 3 * (size_t)vertex_count),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "normals (address");
    CHECK(strstr(mimetic_last_error(), "is not a multiple of 4 bytes") != NULL);
    options.tension = odd;
    options.tension_capacity = 2 * (size_t)vertex_count;
    EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "options->tension (address");
    mimetic_evaluate_options_init(&options);
    options.region_weights = odd;
    options.region_weights_capacity = region_count;
    EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "options->region_weights (address");
    EXPECT_ERROR(mimetic_evaluate(a, odd, muscle_count, 0.f, pos, 3 * (size_t)vertex_count, NULL, 0),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "mimetic_evaluate: activations (address");
    EXPECT_ERROR(mimetic_clip_sample(clip, 0.f, odd, muscle_count, NULL),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "mimetic_clip_sample: activations (address");
    EXPECT_ERROR(mimetic_play(a, clip, 0.f, odd, 3 * (size_t)vertex_count, NULL, 0),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "mimetic_play: positions (address");
    EXPECT_ERROR(mimetic_rig_triangles(rig, (uint32_t*)(void*)odd, 3 * (size_t)triangle_count),
                 MIMETIC_ERROR_INVALID_ARGUMENT, "mimetic_rig_triangles: out (address");
    free(raw);
  }
  mimetic_evaluate_options_init(&options);
  options.positions_stride = 16;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "positions holds");
  mimetic_evaluate_options_init(&options);
  options.tension = tension;
  options.tension_capacity = 2 * (size_t)vertex_count - 1;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "options->tension holds");
  mimetic_evaluate_options_init(&options);
  options.region_weights = weights;
  options.region_weights_capacity = 1;
  EXPECT_ERROR(mimetic_evaluate_ex(a, act, muscle_count, 0.f, &options, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "2 tension regions need 2");
  EXPECT_ERROR(mimetic_context_set_parallel_for(NULL, ReverseThirds, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "context is NULL");
  EXPECT_ERROR(mimetic_rig_tension_region_name(rig, 2, &name), MIMETIC_ERROR_INVALID_ARGUMENT,
               "tension region 2; the rig has 2");
  free(inter);
  free(tension);
  free(weights);

  /* Bad inputs: each its status and a message. */
  snprintf(missing, sizeof missing, "%s/none.mrig", argv[1]);
  EXPECT_ERROR(mimetic_rig_load_file(missing, &bad_rig), MIMETIC_ERROR_IO, "none.mrig: cannot open");
  CHECK(bad_rig == NULL);
  EXPECT_ERROR(mimetic_rig_load_file(argv[1], &bad_rig), MIMETIC_ERROR_IO, "not a regular file");
  EXPECT_ERROR(mimetic_rig_load_memory(mrig, mrig_size / 2, &bad_rig), MIMETIC_ERROR_FORMAT,
               "extend past the end of the file");
  EXPECT_ERROR(mimetic_rig_load_memory(mrig, 10, &bad_rig), MIMETIC_ERROR_FORMAT,
               "header: the file is 10 bytes");
  snprintf(cut_path, sizeof cut_path, "%s/cut.mrig", argv[1]);
  CHECK(WriteAll(cut_path, mrig, mrig_size - 9));
  EXPECT_ERROR(mimetic_rig_load_file(cut_path, &bad_rig), MIMETIC_ERROR_FORMAT, "cut.mrig: section '");
  mrig[mrig_size - 3] ^= 0x40;
  EXPECT_ERROR(mimetic_rig_load_memory(mrig, mrig_size, &bad_rig), MIMETIC_ERROR_FORMAT,
               "checksum mismatch");
  mrig[mrig_size - 3] ^= 0x40;
  EXPECT_ERROR(mimetic_clip_load_memory(mrig, mrig_size, &other),
               MIMETIC_ERROR_FORMAT, "not a compiled clip");
  CHECK(other == NULL);
  EXPECT_ERROR(mimetic_rig_load_memory(mclip, mclip_size, &bad_rig), MIMETIC_ERROR_FORMAT,
               "not a compiled rig");
  EXPECT_ERROR(mimetic_rig_load_file(NULL, &bad_rig), MIMETIC_ERROR_INVALID_ARGUMENT,
               "mimetic_rig_load_file: path is NULL");
  EXPECT_ERROR(mimetic_rig_load_file(path, NULL), MIMETIC_ERROR_INVALID_ARGUMENT, "out is NULL");
  EXPECT_ERROR(mimetic_rig_load_memory(NULL, 100, &bad_rig), MIMETIC_ERROR_INVALID_ARGUMENT,
               "bytes is NULL");
  EXPECT_ERROR(mimetic_rig_get_info(NULL, &info), MIMETIC_ERROR_INVALID_ARGUMENT, "rig is NULL");
  EXPECT_ERROR(mimetic_rig_muscle_name(rig, muscle_count, &name), MIMETIC_ERROR_INVALID_ARGUMENT,
               "the rig has");
  EXPECT_ERROR(mimetic_rig_triangles(rig, triangles, 3 * (size_t)triangle_count - 1),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "triangles need");
  EXPECT_ERROR(mimetic_context_create(NULL, &bad_context), MIMETIC_ERROR_INVALID_ARGUMENT,
               "rig is NULL");
  CHECK(bad_context == NULL);
  EXPECT_ERROR(mimetic_evaluate(NULL, act, muscle_count, 0.f, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "context is NULL");
  EXPECT_ERROR(mimetic_evaluate(a, NULL, muscle_count, 0.f, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "activations is NULL");
  EXPECT_ERROR(mimetic_evaluate(a, act, muscle_count, 0.f, NULL, 0, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "positions is NULL");
  EXPECT_ERROR(mimetic_evaluate(a, act, muscle_count, 0.f, pos, 3 * (size_t)vertex_count - 1, NULL, 0),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "positions holds");
  EXPECT_ERROR(mimetic_evaluate(a, act, muscle_count, 0.f, pos, 3 * (size_t)vertex_count, nrm, 3),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "normals holds 3 floats");
  EXPECT_ERROR(mimetic_evaluate(a, act, muscle_count + 1, 0.f, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_MISMATCH, "activations; the rig has");
  EXPECT_ERROR(mimetic_clip_sample(clip, 0.f, act, muscle_count - 1, NULL),
               MIMETIC_ERROR_BUFFER_TOO_SMALL, "activations holds");
  EXPECT_ERROR(mimetic_clip_sample(NULL, 0.f, act, muscle_count, NULL),
               MIMETIC_ERROR_INVALID_ARGUMENT, "clip is NULL");
  EXPECT_ERROR(mimetic_clip_load_file(missing, &other), MIMETIC_ERROR_IO, "cannot open");
  EXPECT_ERROR(mimetic_play(a, NULL, 0.f, pos, 3 * (size_t)vertex_count, NULL, 0),
               MIMETIC_ERROR_INVALID_ARGUMENT, "clip is NULL");

  /* A clip compiled for another muscle count. */
  snprintf(other_path, sizeof other_path, "%s/other.mclip", argv[1]);
  EXPECT_OK(mimetic_clip_load_file(other_path, &other));
  if (other) {
    EXPECT_OK(mimetic_clip_get_info(other, &clip_info));
    CHECK(clip_info.muscle_count == muscle_count + 1);
    EXPECT_ERROR(mimetic_clip_check_rig(other, rig), MIMETIC_ERROR_MISMATCH,
                 "was compiled for a rig of");
    EXPECT_ERROR(mimetic_play(a, other, 0.5f, pos, 3 * (size_t)vertex_count, NULL, 0),
                 MIMETIC_ERROR_MISMATCH, "this rig has");
  }
  /* A success leaves the last message alone. */
  EXPECT_OK(mimetic_clip_check_rig(clip, rig));
  CHECK(strstr(mimetic_last_error(), "this rig has") != NULL);
  CHECK(strcmp(mimetic_status_name((mimetic_status)99), "unknown status") == 0);

  mimetic_context_destroy(a);
  mimetic_context_destroy(b);
  mimetic_context_destroy(NULL);
  mimetic_clip_destroy(clip);
  mimetic_clip_destroy(other);
  mimetic_rig_destroy(rig);
  mimetic_rig_destroy(NULL);
  free(ref);
  free(mrig);
  free(mclip);
  free(triangles);
  free(act);
  free(pos);
  free(nrm);
  free(pos2);
  free(nrm2);
  if (failures) {
    fprintf(stderr, "capi_test: %d check(s) failed\n", failures);
    return 1;
  }
  printf("capi_test: %u frames bit-identical to the C++ runtime (%u vertices, %u muscles); "
         "bad inputs refused\n", frames, vertex_count, muscle_count);
  return 0;
}
