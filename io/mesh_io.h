// io/mesh_io.h: triangle mesh files (glTF 2.0 through tinygltf, OBJ through OpenMesh's reader).
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"

namespace mimetic {

// Reads a triangle mesh; the format comes from the extension (case-insensitive).
//
// .gltf / .glb (tinygltf): the mesh named `mesh_name`, or the first mesh when it is empty;
// every primitive of it, concatenated in order (vertex and triangle numbers run on across
// primitives). Per primitive: POSITION (float VEC3, required), NORMAL (float VEC3), TEXCOORD_0
// (float, or normalized u8/u16, VEC2), indices (u8/u16/u32 SCALAR, or none = non-indexed).
// Only mode TRIANGLES. Accessor byteOffset and bufferView byteStride are honoured and every
// accessor is bounds-checked against its bufferView and buffer. Before tinygltf sees the
// JSON (the .glb's JSON chunk), it must pass the JSON reader's guard (64 MiB, 64 levels), and
// its structure is checked: extensionsRequired (Draco/meshopt compression and any extension
// that changes geometry are refused), non-negative offsets, lengths and strides, references
// to existing accessors, bufferViews, buffers, meshes and nodes. External buffer URIs are read
// through ReadFile (regular files only, 1 GiB cap). Node transforms: the first node of the
// scene that places the mesh is applied (rotation, translation, mirroring); its uniform scale
// is taken as the file's statement of the unit and not applied, so positions are the scene
// positions in the mesh's own unit (a non-uniform scale or shear is refused). Morph targets
// and skins are ignored with a warning; materials silently. Normals / uvs are kept only when
// every primitive has them (otherwise dropped, with a warning). Images are never decoded.
//
// .obj (OpenMesh's OBJ reader, cross-checked by a validating scan so that nothing OpenMesh
// would silently drop goes unreported): polygons are fan-triangulated from their first corner.
// Vertex layout: vertices 0..#v-1 are the file's `v` lines in order (OBJ index k is vertex
// k-1), each with the texcoord of its first use; every further distinct (v, vt) pair used by a
// face (a UV seam) is appended as an extra vertex in order of first use. `vn` normals are not
// imported (`normals` stays empty; the rig computes normals from the geometry). Texture v is
// flipped (v = 1 - v_obj: OBJ's v runs up, MeshData's as glTF's down). `mtllib` lines are
// ignored with a warning (OpenMesh would open the named file). Faces must use
// distinct vertices and either v/vt on every corner or on none. `mesh_name` is ignored. A file
// with several objects (two or more `o` lines) is read up to its second `o` line: the first
// object alone (as a glTF's first mesh; mimetic writes a rig's companion meshes as further
// objects), whose faces must then use only the vertices written before that line.
//
// Returns false and records every problem in `diag` (capped at 20 messages per kind), naming
// the element: unreadable or empty file, unknown extension, invalid glTF (tinygltf's message),
// missing mesh (listing the available names), unsupported mode, accessor out of bounds,
// attribute count mismatch, `triangle 4: index 99 out of range (mesh has 12 vertices)`,
// `vertex 7: position is not finite`, OBJ `line 12: face 3: references vertex 0, ...`,
// no triangles. `where` names the element only (`triangle 4`, `line 12: face 3`, `mesh 'head'
// primitive 1`; empty for whole-file problems): callers prefix the file, e.g.
// `diag->Append(local, path)`. On failure `out` holds no geometry (only `source`). Never throws.
bool ImportMesh(const std::string& path, const std::string& mesh_name, MeshData* out,
                Diagnostics* diag);

// The same on bytes already in memory (the fuzz targets, fuzz/): `extension` chooses the format
// (".glb", ".gltf", ".obj"), `base_dir` resolves a glTF's buffer URIs. `out->source` is left
// empty.
bool ImportMeshBytes(const std::string& bytes, const std::string& extension,
                     const std::string& base_dir, const std::string& mesh_name, MeshData* out,
                     Diagnostics* diag);

// Writes positions, normals (when present), uvs (when present) and triangles; `.obj` or `.glb`
// by extension. OBJ: `v`/`vt`/`vn` with %.9g (floats round-trip exactly; vt as 1 - v, OBJ's
// convention) and 1-based `f a/a/a ...` faces. GLB: one buffer, POSITION (with min/max),
// NORMAL, TEXCOORD_0, u32 indices, one mesh named "mesh", one node, one scene. glTF's unit is
// the metre: positions are written in mesh units and the node (named "mimetic_units") scales
// them by `metres_per_unit` (0.001 for millimetres; no scale when 1), so viewers show the true
// size and ImportMesh reads the mesh units back unchanged. Refuses (returns false, writes nothing)
// meshes with out-of-range indices, non-finite values or attribute sizes other than 0 or #V.
// The file is written to a temporary name and renamed (WriteFileAtomic).
bool ExportMesh(const std::string& path, const MeshData& mesh, Diagnostics* diag,
                double metres_per_unit = 0.001);

// Several meshes in one file, in order (the first is the one ImportMesh reads when no name is
// given). GLB: one mesh per entry, named as given, each placed by its own node (scaled as
// ExportMesh's), all in the one scene; OBJ: one object (`o NAME`) per entry, indices running
// on (ImportMesh reads the first object). Names must be distinct and not
// empty; each mesh is checked as ExportMesh's (errors name the mesh: `mesh 1 'eyes'`).
// ExportMesh is the one-mesh case, named "mesh".
struct NamedMesh {
  std::string name;
  const MeshData* mesh = nullptr;
};
bool ExportMeshes(const std::string& path, const std::vector<NamedMesh>& meshes,
                  Diagnostics* diag, double metres_per_unit = 0.001);

// The other meshes of a glTF file: every mesh but `mesh_name` (the first when it is empty),
// in file order, each read as ImportMesh reads one (an unnamed mesh is called `mesh_N`, N its
// number). In an OBJ, the objects after the first (`o NAME` lines, ExportMeshes' layout; each
// object's face numbers made its own), `mesh_name` ignored. The rig tools carry these along unchanged
// (the sample head's eyeballs: `mimetic eval`, `play`, `render`). Errors as ImportMesh's,
// prefixed `mesh NAME` for the mesh they concern; on failure `out` is empty. `chosen_name`
// (when given) receives the name of the mesh left out (the rig's), as the file spells it.
struct NamedMeshData {
  std::string name;
  MeshData mesh;
};
bool ImportOtherMeshes(const std::string& path, const std::string& mesh_name,
                       std::vector<NamedMeshData>* out, Diagnostics* diag,
                       std::string* chosen_name = nullptr);

// ImportOtherMeshes' OBJ half on a file's bytes (`base_dir` resolves nothing in an OBJ today;
// it is passed on as ImportMeshBytes takes it): the objects after the first, each with its face
// numbers made its own; an object whose faces reach into an earlier object, or a face index
// that is not a number, is refused naming the object and the line. On failure `out` is empty.
bool ImportOtherObjBytes(const std::string& bytes, const std::string& base_dir,
                         std::vector<NamedMeshData>* out, Diagnostics* diag,
                         std::string* chosen_name = nullptr);

// Metres per unit of a rig's `units` ("mm" 0.001, "cm" 0.01, "dm" 0.1, "m" 1, "in" 0.0254);
// 0 for anything else.
double MetresPerUnit(const std::string& units);

}  // namespace mimetic
