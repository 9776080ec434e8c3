#include "softflow/simulation/remesh_triggers.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "softflow/geometry/object_gaps.hpp"

namespace softflow::simulation {

RemeshTriggers::RemeshTriggers(const io::CaseConfig& config) : settings_(config.remesh) {
  // The mesher refines a gap narrower than gap_elements interface elements
  // (geometry::wall_gap_element_size); wider gaps are meshed as the far
  // field grades and have that many elements across already.
  const geometry::ShearCellSpec spec = config.shear_cell_spec();
  for (const auto& o : spec.objects)
    narrow_gap_ = std::max(narrow_gap_, spec.sizing.elements_across_gaps() *
                                            geometry::interface_element_size(o, spec.sizing));
}

MeshCondition RemeshTriggers::measure(const mesh::Mesh& mesh, double time, double quality) const {
  MeshCondition c;
  c.time = time;
  c.quality = quality;
  if (!(settings_.gap_elements > 0.0)) return c;
  if (const auto gap = geometry::least_resolved_gap(mesh, narrow_gap_)) {
    c.gap_elements = gap->resolution.elements_across();
    c.gap_description =
        gap->other == 0
            ? fmt::format("object {} to the {} wall", gap->object, gap->resolution.side > 0 ? "upper" : "lower")
            : fmt::format("objects {} and {}", gap->object, gap->other);
  }
  return c;
}

std::string RemeshTriggers::due(const MeshCondition& now, double last_remesh_time) const {
  if (settings_.quality > 0.0 && now.quality < settings_.quality &&
      now.quality < 0.95 * quality_fell_short_at_)
    return fmt::format("quality {:.3g} < remesh.quality {:g}", now.quality, settings_.quality);
  if (settings_.gap_elements > 0.0 && now.gap_elements < settings_.gap_elements &&
      now.gap_elements < 0.95 * gap_fell_short_at_)
    return fmt::format("gap of {} crossed by {:.2f} elements < remesh.gap_elements {:g}",
                       now.gap_description, now.gap_elements, settings_.gap_elements);
  // A relative allowance: t accumulates the steps' round-off.
  if (settings_.interval > 0.0 &&
      now.time - last_remesh_time >= settings_.interval * (1.0 - 1e-9))
    return fmt::format("{:.4g} time units since the last remesh >= remesh.interval {:g}",
                       now.time - last_remesh_time, settings_.interval);
  return "";
}

void RemeshTriggers::remeshed(const MeshCondition& after) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  quality_fell_short_at_ = after.quality < settings_.quality ? after.quality : kNone;
  gap_fell_short_at_ = after.gap_elements < settings_.gap_elements ? after.gap_elements : kNone;
}

void RemeshTriggers::failed(const MeshCondition& before) {
  quality_fell_short_at_ = before.quality;
  gap_fell_short_at_ = before.gap_elements;
}

}  // namespace softflow::simulation
