// The readers of each section of a scene file (internal to load_scene).
#pragma once

#include "tools/scene/scene.h"

namespace csim::scene_parts {

void read_parameters(const SceneNode& root, SceneDocument& document);
// Refuses a `--set parameters.NAME=VALUE` that would change the parameter's kind (number or text).
void check_parameter_override(const SceneDocument& document, const std::string& assignment);
void read_references(const SceneNode& root, SceneDocument& document);
void read_materials(const SceneNode& root);
void read_bodies(const SceneNode& root, World& world);
void read_elastic_body(const std::string& name, const SceneNode& node, World& world);
void read_ties(const SceneNode& root, World& world);
void read_springs(const SceneNode& root, World& world);
void read_loads(const SceneNode& root, World& world);
void read_constraints(const SceneNode& root, World& world);
void read_contacts(const SceneNode& root, World& world);
void read_probes(const SceneNode& root, const World& world, RunSettings& run);
void read_checks(const SceneNode& root, RunSettings& run);

// A body named by the value of `key`, or an error naming the key.
int body_named(const SceneNode& node, const std::string& key, const World& world);

// The contact law named by the value of `key`, or an error naming the key.
int contact_law_named(const SceneNode& node, const std::string& key, const World& world);

// The rows [[t, value], ...] of a table (times increasing, else an error naming the row) appended to
// `table`; the caller says what an empty table means.
void read_table_rows(const SceneNode& list, std::vector<std::pair<double, double>>& table);

// The reference coordinates of the node of the one-node set named by key `node`, on an elastic body.
Eigen::Vector3d node_point(const SceneNode& node, const BodyInstance& body);

}  // namespace csim::scene_parts
