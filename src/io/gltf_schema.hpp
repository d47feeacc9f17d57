// The glTF 2.0 core schema, checked over a document's JSON before tinygltf reads it (gltf_schema.cpp). C++ only.
#ifndef RESURF_GLTF_SCHEMA_HPP
#define RESURF_GLTF_SCHEMA_HPP

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

// Checks root (a JSON object) against the glTF 2.0 core schema: JSON types, required properties, array lengths,
// unique items, enum values and numeric ranges. Each problem is one printable line naming the JSON path and the
// cause ("meshes[0].primitives[0].mode: 9 is not a glTF primitive mode (0..6)"); the first `max` of them are
// appended to *problems. Returns how many problems there are in all. An integral number where the schema wants an
// integer (2.0) becomes an integer in root, which tinygltf would otherwise ignore; *rewritten says whether one did.
size_t resurfi_gltf_schema_check(nlohmann::json &root, size_t max, std::vector<std::string> *problems,
                                 bool *rewritten);

#endif
