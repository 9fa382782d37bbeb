#include "app/report.hpp"

#include "asimov/collision/text_file.hpp"

#include "app/atomic_file.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace asimov::app {
namespace {

nlohmann::json vec(const collision::Vec3& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json joints(const robots::JointVector& q) {
  auto out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < q.size(); ++i) out.push_back(q[i]);
  return out;
}

nlohmann::json error_object(const interpreter::Diagnostic& d) {
  return {{"message", d.message}, {"detail", collision::printable(d.detail)}, {"file", collision::printable(d.file)},
          {"line", d.line},       {"column", d.column}, {"program", d.program},
          {"step", d.step}};
}


}  // namespace

const char* status_name(const interpreter::RunResult& r) {
  switch (r.status) {
    case interpreter::RunStatus::completed: return "completed";
    case interpreter::RunStatus::collision: return "collision";
    case interpreter::RunStatus::error: return "error";
    case interpreter::RunStatus::interrupted: return "interrupted";
    case interpreter::RunStatus::paused: return "paused";
    case interpreter::RunStatus::halted: return "halted";
  }
  return "error";
}

nlohmann::json load_error_report(const std::string& file, const interpreter::Diagnostic& first_error) {
  return {{"schema_version", kSchemaVersion}, {"status", "error"}, {"file", file},       {"program", first_error.program},
          {"line", first_error.line}, {"step", first_error.step}, {"sim_time_s", 0.0},
          {"poses_checked", 0},    {"error", error_object(first_error)}};
}

nlohmann::json run_report(const RunSummary& s) {
  const auto& r = s.result;
  nlohmann::json doc = {{"schema_version", kSchemaVersion},
                        {"status", status_name(r)},
                        {"file", s.file},
                        {"program", r.program},
                        {"line", r.line},
                        {"step", r.step},
                        {"sim_time_s", s.sim_time_s},
                        {"poses_checked", s.poses_checked}};
  if (r.status == interpreter::RunStatus::collision) {
    const auto& c = r.collision;
    doc["collision"] = {{"bodies", {c.body_a, c.body_b}},
                        {"point_mm", vec(c.point)},
                        {"joints_deg", joints(c.joints)},
                        {"time_s", c.time_s},
                        {"time_free_s", c.time_free_s},
                        {"toc_bracket_s", c.time_s - c.time_free_s},
                        {"faces", {c.face_a, c.face_b}}};
  }
  if (r.status == interpreter::RunStatus::error || r.status == interpreter::RunStatus::interrupted)
    doc["error"] = error_object(r.error);
  if (r.interrupt)  // Ctrl-C inside a motion: where the arm stopped
    doc["interrupt"] = {{"time_s", r.interrupt->time_s},
                        {"path_fraction", r.interrupt->path_fraction},
                        {"joints_deg", joints(r.interrupt->joints)}};
  if (!r.reaction_stops.empty()) {  // motions a REACTI stopped (docs/val2-dialect.md §7c)
    auto stops = nlohmann::json::array();
    for (const auto& st : r.reaction_stops)
      stops.push_back({{"signal", st.signal}, {"task", st.task}, {"step", st.at.step}, {"time_s", st.at.time_s},
                       {"path_fraction", st.at.path_fraction}, {"joints_deg", joints(st.at.joints)}});
    doc["reaction_stops"] = std::move(stops);
  }
  if (!r.motion_times.empty()) {  // per-motion durations (docs/blending.md)
    auto motions = nlohmann::json::array();
    for (const auto& m : r.motion_times)
      motions.push_back({{"step", m.step}, {"program", m.program}, {"start_s", m.start_s}, {"duration_s", m.duration_s},
                         {"blended", m.blended}});
    doc["motions"] = std::move(motions);
    if (r.motion_times_omitted > 0) doc["motions_omitted"] = r.motion_times_omitted;
  }
  if (!r.warnings.empty()) {
    auto warnings = nlohmann::json::array();
    for (const auto& w : r.warnings) warnings.push_back(error_object(w));
    doc["warnings"] = std::move(warnings);
  }
  doc["collision_engine"] = {{"used", s.engine_used},
                             {"pair_checks", s.counts.pairs_enabled},
                             {"pairs_after_minimax", s.counts.pairs_after_minimax},
                             {"pairs_after_voxels", s.counts.pairs_after_voxels},
                             {"voxel_pairs", s.counts.voxel_pairs},
                             {"face_pairs", s.counts.face_pairs},
                             {"bisection_checks", s.bisection_checks}};
  if (s.workcell.is_object())
    for (const auto& [key, value] : s.workcell.items()) doc[key] = value;
  doc["accuracy"] = accuracy_json(s);
  doc["timing"] = timing_json(s.timing, s.wall_s);
  if (!s.clearance.is_null()) doc["clearance"] = s.clearance;
  return doc;
}

nlohmann::json clearance_json(const motion::Simulator& sim, const std::vector<interpreter::MotionStep>& motions) {
  const motion::CollisionSettings& c = sim.cell().collision;
  auto pairs = nlohmann::json::array();
  for (const motion::ClearanceApproach& a : sim.recorders().clearance.nearest_first()) {
    const interpreter::MotionStep* m = interpreter::motion_at_step(motions, a.step);
    pairs.push_back({{"bodies", {sim.body_name(a.pair.a), sim.body_name(a.pair.b)}},
                     {"distance_mm", a.distance_mm},
                     {"lower_bound_mm", a.lower_bound_mm},
                     {"time_s", a.time_s},
                     {"step", a.step},
                     {"program", m ? m->program : std::string()},  // "" / 0: the step is not one motion's
                     {"line", m ? m->line : 0},
                     {"point_a_mm", vec(a.point_a)},
                     {"point_b_mm", vec(a.point_b)},
                     {"within_clearance", c.clearance_mm > 0 && a.distance_mm <= c.clearance_mm}});
  }
  nlohmann::json doc = {{"report_within_mm", c.report_within_mm},
                         {"clearance_mm", c.clearance_mm},
                         {"on_clearance", c.on_clearance == motion::OnClearance::warn ? "warn" : "halt"},
                         {"continuous", c.continuous}};
  if (!pairs.empty()) doc["closest"] = pairs.front();  // reports hold no null: absent when none
  doc["pairs"] = std::move(pairs);
  return doc;
}

RunSummary summarize_run(const std::string& file, interpreter::RunResult result, const motion::Simulator& sim,
                         double wall_s) {
  RunSummary summary;
  summary.file = file;
  summary.result = std::move(result);
  summary.sim_time_s = sim.time_s();
  summary.poses_checked = sim.recorders().counts.poses;
  summary.counts = sim.recorders().counts.counts;
  summary.engine_used = sim.collision_engine_used();
  summary.bisection_checks = sim.recorders().counts.bisection;
  summary.stepping = sim.cell().collision.stepping;
  summary.accuracy = sim.recorders().accuracy.figures;
  summary.timing = sim.recorders().timing.timing;
  summary.wall_s = wall_s;
  summary.clearance = clearance_json(sim, summary.result.motions);
  summary.closest = interpreter::format_closest(sim, summary.result.motions);
  return summary;
}

nlohmann::json accuracy_json(const RunSummary& s) {
  const motion::RunAccuracy& a = s.accuracy;
  return {{"stepping", s.stepping == motion::Stepping::gap ? "gap" : "fixed"},
          {"motions", a.motions},
          {"step_displacement_mm", a.step_displacement_mm},
          {"contact_bracket_s", a.contacts ? nlohmann::json(a.contact_bracket_s) : nlohmann::json(nullptr)},
          {"ik_residual", {{"position_mm", a.ik_residual.position_mm}, {"rotation_rad", a.ik_residual.rotation_rad},
                           {"solves", a.ik_solves}}},
          {"line_deviation", {{"position_mm", a.line_deviation.position_mm},
                              {"rotation_rad", a.line_deviation.rotation_rad},
                              {"intervals", a.line_intervals}}}};
}

nlohmann::json timing_json(const motion::RunTiming& t, double wall_s) {
  return {{"parse_s", t.parse_s},         {"preprocess_s", t.preprocess_s}, {"motion_s", t.motion_s},
          {"collision_s", t.collision_s}, {"wall_s", wall_s}};
}

nlohmann::json trace_document(const std::string& program, const robots::Robot& robot,
                              const std::vector<motion::TraceSample>& samples) {
  auto rows = nlohmann::json::array();
  for (const auto& s : samples) {
    const auto x = motion::decompose(s.tool);
    rows.push_back({{"t", s.time_s},
                    {"joints_deg", joints(s.joints)},
                    {"tool_xyzoat", {x[0], x[1], x[2], x[3], x[4], x[5]}}});
    if (!s.part.empty()) {  // the carried part (docs/cell-format.md "Collision bodies")
      const auto p = motion::decompose(s.part_pose);
      rows.back()["part"] = s.part;
      rows.back()["part_xyzoat"] = {p[0], p[1], p[2], p[3], p[4], p[5]};
    }
  }
  return {{"schema_version", kSchemaVersion},
          {"program", program},
          {"robot", robot.name},
          {"units", {{"t", "s"}, {"joints_deg", "deg"}, {"tool_xyzoat", "mm, deg (VAL O/A/T)"}}},
          {"samples", std::move(rows)}};
}

Result<void> write_json_file(const std::string& path, const nlohmann::json& doc) {
  return write_file_atomically(path, doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

std::string collision_lines(const motion::CollisionReport& c) {
  std::string out = fmt::format("at t = {:.6f} s, point ({:.3f}, {:.3f}, {:.3f}) mm\njoints", c.time_s,
                                c.point.x(), c.point.y(), c.point.z());
  for (Eigen::Index i = 0; i < c.joints.size(); ++i) out += fmt::format(" {:.3f}", c.joints[i]);
  return out + '\n';
}

}  // namespace asimov::app
