// tests/io/schema_test.cpp: the JSON Schemas in assets/schema/ are generated from the reader's
// tables (json_reader::Schema), so the schema and the reader cannot drift. To regenerate them
// after changing a table:
//   MIMETIC_UPDATE_SCHEMAS=1 ./build/tests/io_schema_test
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/formats.h"
#include "io/json_reader.h"
#include "test_support.h"

namespace mimetic {
namespace {

struct SchemaFile {
  const json_reader::Format& format;
  std::string file;  // under assets/schema/
  std::vector<std::string> examples;  // files the schema must accept, under the source dir
};

std::vector<SchemaFile> Schemas() {
  return {{RigFileFormat(), "mimetic-rig.schema.json", {"assets/head/sample_head.rig.json"}},
          {TemplateFileFormat(), "mimetic-muscle-template.schema.json",
           {"assets/head/default.template.json"}},
          {LandmarksFileFormat(), "mimetic-landmarks.schema.json",
           {"assets/head/sample_head.landmarks.json",
            "tests/data/landmarks/ict_facekit.landmarks.json"}},
          {ExpressionFileFormat(), "mimetic-expression.schema.json",
           {"tests/data/expressions/smile_L.expression.json"}},
          {ClipFileFormat(), "mimetic-clip.schema.json",
           {"tests/data/clips/smile_blink.clip.json", "assets/clips/surprise.clip.json",
            "assets/clips/frowning.clip.json", "assets/clips/fear.clip.json",
            "assets/clips/smile.clip.json"}},
          {ExpressionLibraryFormat(), "mimetic-expression-library.schema.json",
           {"assets/expressions/default.library.json"}},
          {ArkitMapFormat(), "mimetic-arkit-map.schema.json", {"assets/arkit/default.arkit.json"}},
          {ArkitTakeFormat(), "mimetic-arkit-take.schema.json", {"tests/data/arkit/take.json"}}};
}

TEST(Schema, CommittedSchemasAreTheOnesGeneratedFromTheTables) {
  const bool update = std::getenv("MIMETIC_UPDATE_SCHEMAS") != nullptr;
  for (const SchemaFile& s : Schemas()) {
    SCOPED_TRACE(s.file);
    const std::string path = test::SourceDir() + "/assets/schema/" + s.file;
    const nlohmann::json generated = json_reader::Schema(s.format);
    if (update) std::ofstream(path, std::ios::binary) << generated.dump(2) << "\n";
    const nlohmann::json committed = nlohmann::json::parse(test::ReadFileBytes(path), nullptr, false);
    ASSERT_FALSE(committed.is_discarded()) << path << " is missing or not JSON";
    EXPECT_EQ(committed, generated)
        << path << " differs from the reader's tables; regenerate it with "
        << "MIMETIC_UPDATE_SCHEMAS=1 ./build/tests/io_schema_test";
  }
}

// The tables and the schema describe the same keys: every declared field is a property, with
// the same required-ness (a walk over the rig's top level and its muscles).
TEST(Schema, RigSchemaHasTheTablesKeysAndRequiredness) {
  const nlohmann::json schema = json_reader::Schema(RigFileFormat());
  const json_reader::Object& top = *RigFileFormat().root.object;
  for (const json_reader::Field& f : top.fields) {
    SCOPED_TRACE(f.key);
    ASSERT_TRUE(schema["properties"].contains(f.key));
    const auto& req = schema["required"];
    EXPECT_EQ(std::find(req.begin(), req.end(), f.key) != req.end(), f.required);
  }
  EXPECT_EQ(schema["properties"].size(), top.fields.size());
  EXPECT_EQ(schema["additionalProperties"], false);
  // Muscles: one if/then per type, each closing the keys of its type.
  const nlohmann::json& muscle = schema["properties"]["muscles"]["items"];
  ASSERT_EQ(muscle["allOf"].size(), 2u);
  EXPECT_EQ(muscle["allOf"][0]["if"]["properties"]["type"]["const"], "linear");
  EXPECT_EQ(muscle["allOf"][0]["then"]["additionalProperties"], false);
  EXPECT_EQ(muscle["allOf"][0]["then"]["properties"]["zone_angle_deg"]["exclusiveMaximum"], 180.0);
  EXPECT_EQ(muscle["allOf"][1]["then"]["properties"]["wrinkles"]["properties"]["count"]["minimum"], 1);
}

bool HavePythonJsonschema() {
  return std::system("python3 -c 'import jsonschema' >/dev/null 2>&1") == 0;
}

TEST(Schema, ExampleFilesValidateAgainstTheSchemas) {
  if (!HavePythonJsonschema()) {
    // tools/install-deps.sh installs it: under CI a missing validator is a failure, not a skip.
    if (std::getenv("CI")) FAIL() << "python3 with jsonschema is not installed (CI=true)";
    GTEST_SKIP() << "python3 with jsonschema is not installed";
  }
  for (const SchemaFile& s : Schemas()) {
    for (const std::string& example : s.examples) {
      SCOPED_TRACE(example);
      const std::string cmd =
          "python3 -c 'import json, sys, jsonschema; "
          "jsonschema.Draft7Validator.check_schema(json.load(open(sys.argv[1]))); "
          "jsonschema.validate(json.load(open(sys.argv[2])), json.load(open(sys.argv[1])))' '" +
          test::SourceDir() + "/assets/schema/" + s.file + "' '" + test::SourceDir() + "/" +
          example + "' 2>&1";
      EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    }
  }
}

}  // namespace
}  // namespace mimetic
