#include "rig/runtime/rig.h"

#include <atomic>

#include "rig/runtime/rig_tables.h"

namespace mimetic {
namespace {

std::atomic<uint64_t> g_next_uid{1};

template <class T>
size_t Bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

bool Rig::Build(RigData data, Rig* out) {
  Rig rig;
  rig.data_ = std::move(data);
  rig.id_.checked = CheckRigData(rig.data_);
  if (rig.id_.checked) BuildRigTables(rig.data_, &rig.tables_);
  rig.id_.uid = g_next_uid.fetch_add(1);
  *out = std::move(rig);
  return out->tables_checked();
}

int Rig::FindMuscle(std::string_view name) const {
  for (size_t i = 0; i < data_.muscle_names.size(); ++i)
    if (data_.muscle_names[i] == name) return int(i);
  return -1;
}

size_t Rig::ByteSize() const {
  const RigData& d = data_;
  size_t n = sizeof(Rig);
  n += Bytes(d.rest_points) + Bytes(d.triangles) + Bytes(d.point_triangle_offsets) +
       Bytes(d.point_triangles);
  n += Bytes(d.vertex_points) + Bytes(d.vertex_indices) + Bytes(d.vertex_uvs);
  n += Bytes(d.point_thickness) + Bytes(d.rest_triangle_areas);
  n += Bytes(d.muscle_wrinkles);
  for (const RigMuscleWrinkles& w : d.muscle_wrinkles)
    n += Bytes(w.points) + Bytes(w.phase) + Bytes(w.attenuation) + Bytes(w.profile) +
         Bytes(w.edge_offsets) + Bytes(w.edge_neighbors) + Bytes(w.edge_rest_lengths) +
         Bytes(w.edge_weights);
  const RigCurveWrinkles& c = d.curve_wrinkles;
  n += Bytes(c.names) + Bytes(c.wrinkles) + Bytes(c.points) + Bytes(c.offsets) +
       Bytes(c.entries) + Bytes(c.probes);
  n += Bytes(d.muscle_names) + Bytes(d.muscles.offsets) + Bytes(d.muscles.entries);
  n += Bytes(d.jaw.points) + Bytes(d.jaw.weights);
  n += Bytes(d.eyes.centers) + Bytes(d.eyes.points) + Bytes(d.eyes.eyes) + Bytes(d.eyes.radii) +
       Bytes(d.eyes.weights);
  const RigTensionRegions& g = d.tension_regions;
  n += Bytes(g.names) + Bytes(g.references) + Bytes(g.offsets) + Bytes(g.points) +
       Bytes(g.weights);
  n += Bytes(d.fine_scale.probes);
  const RigTables& t = tables_;
  n += Bytes(t.rest_faces) + Bytes(t.rest_point_normals) + Bytes(t.edge_pairs) +
       Bytes(t.row_offsets) + Bytes(t.entry_edges) + Bytes(t.entry_rest) +
       Bytes(t.entry_coeffs) + Bytes(t.row_profiles) + Bytes(t.row_muscles) + Bytes(t.probe_edges) +
       Bytes(t.point_row_offsets) + Bytes(t.point_curve_offsets) + Bytes(t.point_curve_rows) +
       Bytes(t.wrinkle_points) + Bytes(t.point_neighbor_offsets) + Bytes(t.point_neighbors) +
       Bytes(t.point_neighbor_edges) + Bytes(t.neighbor_edge_pairs) +
       Bytes(t.fine_edge_pairs) + Bytes(t.fine_probe_edges) +
       Bytes(t.fine_probe_params);
  return n;
}

}  // namespace mimetic
