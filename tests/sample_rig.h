// tests/sample_rig.h: the bundled sample head's rig, changed by a test and saved under a
// temporary directory (paths made absolute so the copy loads from anywhere).
#pragma once

#include <fstream>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace mimetic::test {

inline std::string EditedSampleRig(const std::string& name,
                                   const std::function<void(nlohmann::json&)>& edit) {
  std::ifstream in(SourceDir() + "/assets/head/sample_head.rig.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["mesh"]["path"] = SourceDir() + "/assets/head/sample_head.glb";
  j["thickness"]["path"] = SourceDir() + "/assets/head/sample_head.thickness.png";
  edit(j);
  const std::string path = TempDir() + "/" + name + ".rig.json";
  std::ofstream(path) << j.dump(1);
  return path;
}

// The sample head's rig without its jaw (a rig on which jaw values do nothing).
inline std::string SampleRigWithoutJaw() {
  return EditedSampleRig("nojaw", [](nlohmann::json& j) { j.erase("jaw"); });
}

}  // namespace mimetic::test
