// The report's "events" and "parts" for a cell with parts or devices (docs/cell-format.md).
#include "report.hpp"

#include "asimov/motion/location.hpp"

namespace asimov::app {

const char* part_state_name(motion::Holder h) {
  switch (h) {
    case motion::Holder::world: return "resting";
    case motion::Holder::conveyor: return "on_conveyor";
    case motion::Holder::carried: return "carried";
    case motion::Holder::removed: return "removed";
  }
  return "resting";
}

nlohmann::json event_json(const motion::CellEvent& e) {
  nlohmann::json j = {{"time_s", e.time_s}, {"kind", e.kind}, {"subject", e.subject}};
  if (!e.detail.empty()) j["detail"] = e.detail;
  if (e.line > 0) j["line"] = e.line;
  return j;
}

nlohmann::json workcell_json(const motion::CellRuntime& cell) {
  const auto& clock = cell.clock();
  auto events = nlohmann::json::array();
  for (const auto& e : clock.events()) events.push_back(event_json(e));
  auto parts = nlohmann::json::array();
  for (std::size_t i = 0; i < clock.parts().size(); ++i) {
    const auto& p = clock.parts()[i];
    const motion::Location pose = clock.part_pose(i);
    const auto oat = motion::decompose(pose);
    nlohmann::json j = {{"name", p.def->name},
                        {"state", part_state_name(p.holder)},
                        {"pose", {oat[0], oat[1], oat[2], oat[3], oat[4], oat[5]}}};
    if (!p.def->colour.empty()) j["colour"] = p.def->colour;
    if (const std::string on = cell.resting_on(i); !on.empty()) j["on"] = on;
    parts.push_back(std::move(j));
  }
  // The signals on at the end of the run (outputs, inputs, soft signals), ascending.
  const std::vector<int> on(clock.signals().begin(), clock.signals().end());
  nlohmann::json j = {{"events", std::move(events)}, {"parts", std::move(parts)}, {"signals_on", on}};
  // Past motion::kMaxEvents the events are counted, not kept (docs/limits.md).
  if (clock.events_dropped() > 0) j["events_dropped"] = clock.events_dropped();
  return j;
}

}  // namespace asimov::app
