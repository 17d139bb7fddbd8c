#!/usr/bin/env python3
"""Writes the bad-input corpus of tests/data/bad (run from anywhere; the files are checked in,
this script documents how each was made). tests/bad_inputs_test.sh runs every one through the
CLI as listed in cases.txt."""
import base64, json, os, struct

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.normpath(os.path.join(here, '..', '..', '..'))
os.chdir(here)

def write(name, data):
    mode = 'wb' if isinstance(data, bytes) else 'w'
    with open(name, mode) as f:
        f.write(data)

# A valid one-triangle glTF with an embedded buffer: the base the glTF cases break.
positions = struct.pack('<9f', 0, 0, 0, 10, 0, 0, 0, 10, 0)
indices = struct.pack('<3H', 0, 1, 2) + b'\0\0'
blob = positions + indices
def tri(**changes):
    g = {
        'asset': {'version': '2.0'},
        'buffers': [{'byteLength': len(blob),
                     'uri': 'data:application/octet-stream;base64,' + base64.b64encode(blob).decode()}],
        'bufferViews': [{'buffer': 0, 'byteOffset': 0, 'byteLength': 36},
                        {'buffer': 0, 'byteOffset': 36, 'byteLength': 6}],
        'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': 3, 'type': 'VEC3',
                       'min': [0, 0, 0], 'max': [10, 10, 0]},
                      {'bufferView': 1, 'componentType': 5123, 'count': 3, 'type': 'SCALAR'}],
        'meshes': [{'name': 'tri', 'primitives': [{'attributes': {'POSITION': 0}, 'indices': 1}]}],
        'nodes': [{'mesh': 0}],
        'scenes': [{'nodes': [0]}],
        'scene': 0,
    }
    for k, v in changes.items():
        path = k.split('__')
        obj = g
        for p in path[:-1]:
            obj = obj[int(p)] if p.isdigit() else obj[p]
        obj[path[-1]] = v
    return g

def gltf(name, g):
    write(name, json.dumps(g))

gltf('draco_required.gltf', tri(extensionsRequired=['KHR_draco_mesh_compression'],
                                extensionsUsed=['KHR_draco_mesh_compression']))
gltf('meshopt_required.gltf', tri(extensionsRequired=['EXT_meshopt_compression'],
                                  extensionsUsed=['EXT_meshopt_compression']))
gltf('unsupported_extension_required.gltf', tri(extensionsRequired=['KHR_mesh_quantization'],
                                                extensionsUsed=['KHR_mesh_quantization']))
gltf('negative_byte_offset.gltf', tri(accessors__0__byteOffset=-4))
gltf('negative_byte_stride.gltf', tri(bufferViews__0__byteStride=-12))
gltf('missing_accessor.gltf', tri(meshes__0__primitives__0__attributes={'POSITION': 7}))
gltf('missing_buffer_view.gltf', tri(accessors__1__bufferView=5))
gltf('missing_mesh_in_node.gltf', tri(nodes=[{'mesh': 3}]))
gltf('node_nonuniform_scale.gltf', tri(nodes=[{'mesh': 0, 'scale': [1, 2, 1]}]))
gltf('buffer_uri_missing.gltf', tri(buffers=[{'byteLength': len(blob), 'uri': 'no_such_buffer.bin'}]))
gltf('buffer_uri_directory.gltf', tri(buffers=[{'byteLength': len(blob), 'uri': '.'}]))
gltf('accessor_past_buffer_view.gltf', tri(accessors__0__count=300))
write('invalid_json.gltf', '{"asset": {"version": "2.0"}, "meshes": [')
deep = 'x' * 0
write('deep_extras.gltf', json.dumps(tri())[:-1] + ', "extras": ' + '[' * 5000 + ']' * 5000 + '}')

# GLB containers.
with open(os.path.join(root, 'assets', 'head', 'sample_head.glb'), 'rb') as f:
    head = f.read()
write('truncated.glb', head[:4096])
write('not_a_glb.glb', b'this is a text file, not binary glTF\n')
write('empty.glb', b'')
json_chunk = (json.dumps(tri())[:-1] + ', "extras": ' + '{"a":' * 3000 + '1' + '}' * 3000 + '}').encode()
json_chunk += b' ' * (-len(json_chunk) % 4)
# A header length below the 20 bytes of header + chunk header (found by fuzz_mesh_glb).
write('glb_length_below_header.glb', b'glTF' + struct.pack('<II', 2, 11) + struct.pack('<I', 736) +
      b'JSON' + json.dumps(tri()).encode())
write('deep_json_chunk.glb', b'glTF' + struct.pack('<II', 2, 20 + len(json_chunk)) +
      struct.pack('<I', len(json_chunk)) + b'JSON' + json_chunk)

# OBJ.
write('index_out_of_range.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n')
write('nan_vertex.obj', 'v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n')
write('no_faces.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\n')
write('glb_bytes_named.obj', head[:2048])
write('wrong_extension.stl', 'solid x\nendsolid x\n')

# Images (through a rig's thickness image).
with open(os.path.join(root, 'assets', 'head', 'sample_head.thickness.png'), 'rb') as f:
    png = f.read()
write('truncated.png', png[:200])
write('not_a_png.png', 'plain text, not an image\n')

# Rigs (mesh and image paths relative to this folder).
with open(os.path.join(root, 'assets', 'head', 'sample_head.rig.json')) as f:
    rig = json.load(f)
mesh_rel = '../../../assets/head/sample_head.glb'
def rigfile(name, change):
    r = json.loads(json.dumps(rig))
    r['mesh']['path'] = mesh_rel
    r['thickness'] = {'type': 'constant', 'value': 3.0}
    change(r)
    write(name, json.dumps(r, indent=1))
rigfile('rig_units_not_string.json', lambda r: r.__setitem__('units', 5))
rigfile('rig_mesh_missing.json', lambda r: r['mesh'].__setitem__('path', 'no_such_mesh.glb'))
rigfile('rig_truncated_png.json', lambda r: r.__setitem__(
    'thickness', {'type': 'image', 'path': 'truncated.png', 'min': 0, 'max': 5}))
rigfile('rig_not_a_png.json', lambda r: r.__setitem__(
    'thickness', {'type': 'image', 'path': 'not_a_png.png', 'min': 0, 'max': 5}))
rigfile('rig_mesh_truncated_glb.json', lambda r: r['mesh'].__setitem__('path', 'truncated.glb'))
# A small rig (one muscle) asking for fall-off refinement of a whole peak (docs/model.md §11).
write('rig_falloff_error_one.json', json.dumps(
    {'format': 'mimetic-rig', 'version': 1, 'mesh': {'path': mesh_rel}, 'units': 'mm',
     'muscles': [rig['muscles'][0]], 'refinement': {'enabled': True, 'falloff_error': 1}},
    indent=1) + '\n')
# A small rig whose one muscle's furrows open fully at activation 2, past 1 (docs/model.md §6).
write('rig_wrinkle_gate_two.json', json.dumps(
    {'format': 'mimetic-rig', 'version': 1, 'mesh': {'path': mesh_rel}, 'units': 'mm',
     'muscles': [dict(rig['muscles'][0], wrinkles=dict(rig['muscles'][0]['wrinkles'], gate=2))]},
    indent=1) + '\n')
# Small rigs (one muscle) with a bad eyes block (docs/model.md §24) and a bad jaw key (§18).
write('rig_eye_radius_negative.json', json.dumps(
    {'format': 'mimetic-rig', 'version': 1, 'mesh': {'path': mesh_rel}, 'units': 'mm',
     'muscles': [rig['muscles'][0]],
     'eyes': {'spheres': [{'center': [-32, 36, 62], 'radius': -12}], 'band': [2, 8]}},
    indent=1) + '\n')
write('rig_jaw_thickness_fade_two.json', json.dumps(
    {'format': 'mimetic-rig', 'version': 1, 'mesh': {'path': mesh_rel}, 'units': 'mm',
     'muscles': [rig['muscles'][0]], 'jaw': dict(rig['jaw'], thickness_fade=2)},
    indent=1) + '\n')
def bad_field_and_missing_mesh(r):
    r['units'] = 'furlong'
    r['mesh']['path'] = 'no_such_mesh.glb'
rigfile('rig_bad_field_and_missing_mesh.json', bad_field_and_missing_mesh)
text = json.dumps(dict(rig, mesh={'path': mesh_rel}, thickness={'type': 'constant', 'value': 3.0}))
write('rig_overflowing_number.json', text.replace('"strength": ', '"strength": 1e400, "x": ', 1))
write('rig_not_json.json', text[: len(text) // 2])
write('rig_top_level_array.json', '[1, 2, 3]\n')
write('rig_deep_nesting.json', '{"format": "mimetic-rig", "extras": ' + '[' * 1000 + ']' * 1000 + '}')
write('rig_binary_garbage.json', bytes(range(256)))

# Landmarks and templates (through fit).
write('landmarks_overflowing_version.json', '{"format":"mimetic-landmarks","version":1e400}\n')
write('landmarks_deep_nesting.json', '[' * 5000 + ']' * 5000)
write('landmarks_not_json.json', '{"format": "mimetic-landmarks", "version": 1, "points": [[1, 2,')
write('template_not_json.template.json', '{"format": "mimetic-template",')
write('template_wrong_format.template.json', '{"format": "mimetic-rig", "version": 1}\n')
# A template whose one sliding muscle (the default template's first) averages normals over a
# negative radius.
with open(os.path.join(root, 'assets', 'head', 'default.template.json')) as f:
    muscle = json.load(f)['muscles'][0]
# ... and one that asks for fall-off refinement below zero (docs/model.md §11).
write('template_negative_falloff_error.template.json', json.dumps(
    {'format': 'mimetic-muscle-template', 'version': 1, 'muscles': [muscle],
     'refinement': {'falloff_error': -0.1}}, indent=1) + '\n')
muscle['tangent_radius'] = -0.5
write('template_negative_tangent_radius.template.json', json.dumps(
    {'format': 'mimetic-muscle-template', 'version': 1, 'muscles': [muscle]}, indent=1) + '\n')

# Clips (through play, on the surface rig).
def clipfile(name, channels, **top):
    c = {'format': 'mimetic-clip', 'version': 1, 'name': 'bad'}
    c.update(top)
    c['channels'] = channels
    write(name, json.dumps(c, indent=1) + '\n')
clipfile('clip_unsorted_keys.clip.json',
         [{'muscle': 'zygomatic', 'keys': [{'t': 1.0, 'v': 0.5}, {'t': 0.5, 'v': 1.0}]}])
clipfile('clip_unknown_muscle.clip.json', [{'muscle': 'zygomatc', 'keys': [{'t': 0, 'v': 1}]}])
clipfile('clip_value_above_one.clip.json', [{'muscle': 'frontalis', 'keys': [{'t': 0, 'v': 1.5}]}])
write('clip_not_json.clip.json', '{"format": "mimetic-clip", "version": 1, "channels": [')

# ARKit takes (through import-arkit, on the sample head with the default map).
write('take_weight_above_one.csv', 'Timecode,BlendShapeCount,JawOpen\n00:00:00:00,1,0.5\n00:00:00:01,1,1.5\n')
write('take_bad_timecode.csv', 'Timecode,JawOpen\n00:00:00:00,0.5\n00:00:00:75,0.2\n')
write('take_not_json.json', '[{"time": 0, "blendshapes": {')
