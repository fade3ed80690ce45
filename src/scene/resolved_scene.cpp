#include "scene/resolved_scene.h"

#include <filesystem>

namespace tissu {

namespace {

std::string absolute_path(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

}  // namespace

Json material_json(const Material& material) {
  Json m = {{"density", material.density},
            {"stiffness", {{"weft", material.weft},
                           {"warp", material.warp},
                           {"coupling", material.coupling},
                           {"shear", material.shear}}},
            {"bending", material.bending}};
  if (material.bending_warp >= 0.0) m["bending_warp"] = material.bending_warp;
  m["damping"] = material.damping;
  if (material.compression_ratio < 1.0) m["compression_ratio"] = material.compression_ratio;
  return m;
}

Json resolved_scene(const Json& doc, const Scene& scene) {
  Json out = doc;
  Json& cloth = out["cloth"];
  // A preset, by name or with overrides, becomes its numbers.
  const Json& material = cloth["material"];
  if (material.is_string() || (material.is_object() && material.contains("preset"))) {
    cloth["material"] = material_json(scene.material);
  }
  if (scene.mesh.kind == MeshSpec::Kind::File) {
    cloth["mesh"]["file"] = absolute_path(scene.mesh.file);
  }
  for (const ObstacleMeshSpec& mesh : scene.obstacle_meshes) {
    out["obstacles"][mesh.obstacle]["mesh"]["file"] = absolute_path(mesh.file);
  }
  return out;
}

}  // namespace tissu
