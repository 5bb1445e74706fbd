#include "summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "coopnav/assessment/path_assessment.hpp"
#include "transcript.hpp"

namespace coopnav::ctl {
namespace {

Json tristateJson(std::int8_t pred) {
  if (pred == situation_t::PRED_TRUE) return Json::boolean(true);
  if (pred == situation_t::PRED_FALSE) return Json::boolean(false);
  return Json::null();
}

std::string recordingName(std::int8_t rec) {
  switch (rec) {
    case path_assessment_t::REC_IDLE:
      return "IDLE";
    case path_assessment_t::REC_RECORDING:
      return "RECORDING";
    case path_assessment_t::REC_STOPPED:
      return "STOPPED";
    default:
      return "REC_" + std::to_string(rec);
  }
}

Json cmByGamma(const std::vector<double>& ca_m) {
  Json o = Json::object();
  for (const double gamma : kSummaryGammas) {
    char key[16];
    std::snprintf(key, sizeof key, "%.2f", gamma);
    o.set(key, Json::number(assessment::discountedMean(ca_m, gamma)));
  }
  return o;
}

Json point(double x, double y) { return Json::array().push(Json::number(x)).push(Json::number(y)); }

// [m] Minimum robot-human clearance (centre distance minus radii) over the logged states; NaN
// when no state has both.
double minClearanceFromStates(const RunLog& run) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& s : run.agent_states) {
    for (const auto& h : s.humans) {
      const double d =
          std::hypot(h.x_m - s.robot.x_m, h.y_m - s.robot.y_m) - h.radius_m - s.robot.radius_m;
      if (std::isfinite(d)) best = std::min(best, d);
    }
  }
  return std::isfinite(best) ? best : std::nan("");
}

Json humanEntry(const RunLog& run, const HumanAnalysis& h,
                const std::vector<TranscriptEntry>& transcript) {
  Json o = Json::object();
  o.set("id", Json::number(std::int64_t{h.id}));
  const path_assessment_t* p = h.last_assessment ? &run.assessments[*h.last_assessment] : nullptr;
  if (p) {
    o.set("cm_window_m", Json::number(p->cm_m));
    o.set("window_samples", Json::number(std::int64_t{p->window_samples}));
    o.set("is_contributing", tristateJson(p->is_contributing));
    o.set("cm_interaction_m", Json::number(p->cm_interaction_m));
    o.set("interaction_samples", Json::number(std::int64_t{p->interaction_samples}));
    o.set("is_contributing_interaction", tristateJson(p->is_contributing_interaction));
    o.set("gamma", Json::number(p->gamma));
    o.set("tau_m", Json::number(p->tau_m));
    o.set("recording", Json::string(recordingName(p->recording)));
    o.set("cm_by_gamma", cmByGamma(p->ca_m));
    o.set("cm_by_gamma_complete", Json::boolean(p->num_samples == p->window_samples));
  } else {
    for (const char* k : {"cm_window_m", "window_samples", "is_contributing", "cm_interaction_m",
                          "interaction_samples", "is_contributing_interaction", "gamma", "tau_m",
                          "recording", "cm_by_gamma"})
      o.set(k, Json::null());
    o.set("cm_by_gamma_complete", Json::boolean(false));
  }
  o.set("cm_interaction_by_gamma",
        h.interaction_ca_complete ? cmByGamma(h.interaction_ca_m) : Json::null());
  o.set("interaction_ca_complete", Json::boolean(h.interaction_ca_complete));
  // The CA itself, so that figures across scenarios (paper's γ-vs-CM plot) need only this file.
  const std::vector<double>* ca = h.interaction_ca_complete ? &h.interaction_ca_m
                                  : p                       ? &p->ca_m
                                                            : nullptr;
  o.set("ca_kind",
        ca ? Json::string(h.interaction_ca_complete ? "interaction" : "window") : Json::null());
  Json ca_json = Json::array();
  if (ca)
    for (const double v : *ca) ca_json.push(Json::number(v));
  o.set("ca_m", std::move(ca_json));
  o.set("recorder_start_s", Json::number(h.recorder_start_s));
  o.set("docked", Json::boolean(h.docked));
  bool thanked = false;
  for (const auto& u : run.utterances)
    thanked = thanked || (u.human_id == h.id && u.speech_act == utterance_t::ACT_THANK);
  o.set("thanked", Json::boolean(thanked));

  if (h.first_round_situation) {
    const auto& s = run.situations[*h.first_round_situation];
    Json r = Json::object();
    r.set("t_s", Json::number(utimeToS(s.utime)));
    r.set("t_cross_s", Json::number(s.t_cross_s));
    r.set("cp_h_m", point(s.cp_h_x_m, s.cp_h_y_m));
    r.set("cp_r_m", point(s.cp_r_x_m, s.cp_r_y_m));
    r.set("dir", Json::string(directionName(s.dir)));
    r.set("d_h_m", Json::number(s.d_h_m));
    r.set("human_needs_to_contribute", tristateJson(s.human_needs_to_contribute));
    r.set("human_is_constrained", tristateJson(s.human_is_constrained));
    r.set("robot_is_constrained", tristateJson(s.robot_is_constrained));
    o.set("first_round", r);
  } else {
    o.set("first_round", Json::null());
  }

  Json entries = Json::array();
  using Kind = TranscriptEntry::Kind;
  for (const auto& e : transcript) {
    if (e.human_id != h.id) continue;
    if (e.kind != Kind::kSay && e.kind != Kind::kAction && e.kind != Kind::kRecorder) continue;
    Json j = Json::object();
    j.set("t_s", Json::number(utimeToS(e.utime)));
    j.set("t_cross_s", Json::number(e.t_cross_s));
    if (e.kind == Kind::kSay) {
      j.set("kind", Json::string("say"));
      j.set("act", Json::string(e.what));
      j.set("text", Json::string(e.text));
      j.set("round", Json::number(std::int64_t{e.round}));
      j.set("direction", Json::string(e.direction));
    } else {
      j.set("kind", Json::string(e.kind == Kind::kAction ? "action" : "recorder"));
      j.set(e.kind == Kind::kAction ? "action" : "command", Json::string(e.what));
      j.set("reason", Json::string(e.text));
    }
    entries.push(std::move(j));
  }
  o.set("transcript", std::move(entries));
  return o;
}

}  // namespace

Json summarizeRun(const RunLog& run, const RunAnalysis& analysis, const std::string& log_name) {
  TranscriptOptions topt;
  topt.include_unknown = false;
  topt.include_final_cm = false;
  topt.include_sim_status = false;
  const auto transcript = buildTranscript(run, analysis, topt);

  Json s = Json::object();
  s.set("scenario", Json::string(analysis.scenario));
  s.set("log", Json::string(log_name));
  const sim_status_t* st =
      analysis.final_status ? &run.sim_status[*analysis.final_status] : nullptr;
  if (st) {
    s.set("final_state", Json::string(simStateName(st->state)));
    s.set("collision", Json::boolean(st->state == sim_status_t::STATE_COLLISION));
    s.set("min_clearance_m", Json::number(st->min_clearance_m));
    s.set("robot_time_to_goal_s", Json::number(st->robot_time_to_goal_s));
    s.set("sim_time_s", Json::number(utimeToS(st->utime)));
    s.set("last_step", Json::number(st->step));
    s.set("detail", Json::string(st->detail));
  } else {
    for (const char* k : {"final_state", "collision", "min_clearance_m", "robot_time_to_goal_s",
                          "sim_time_s", "last_step", "detail"})
      s.set(k, Json::null());
  }
  s.set("min_clearance_states_m", Json::number(minClearanceFromStates(run)));
  bool docked = false;
  for (const auto& h : analysis.humans) docked = docked || h.docked;
  s.set("docked", Json::boolean(docked));

  Json humans = Json::array();
  for (const auto& h : analysis.humans) humans.push(humanEntry(run, h, transcript));
  s.set("humans", std::move(humans));

  const auto& c = run.counts;
  Json counts = Json::object();
  counts.set("events", Json::number(c.events));
  counts.set("decoded", Json::number(c.decoded));
  counts.set("not_needed", Json::number(c.not_needed));
  counts.set("undecodable", Json::number(c.undecodable));
  counts.set("unknown_channel", Json::number(c.unknown_channel));
  counts.set("bad_headers", Json::number(c.bad_headers));
  counts.set("skipped_bytes", Json::number(c.skipped_bytes));
  counts.set("truncated", Json::boolean(c.truncated));
  s.set("log_counts", std::move(counts));
  return s;
}

Json summaryDocument(const std::vector<Json>& scenario_entries) {
  Json doc = Json::object();
  doc.set("format", Json::string(kSummaryFormat));
  Json list = Json::array();
  for (const auto& e : scenario_entries) list.push(e);
  doc.set("scenarios", std::move(list));
  return doc;
}

Json mergeSummaries(const std::vector<Json>& documents) {
  std::vector<Json> merged;
  for (const auto& doc : documents) {
    const Json* list = doc.type() == Json::Type::kObject ? doc.find("scenarios") : nullptr;
    if (!list || list->type() != Json::Type::kArray)
      throw std::runtime_error("not a coopnav summary (no \"scenarios\" array)");
    for (const auto& entry : list->items()) {
      const Json* name = entry.find("scenario");
      const std::string key = name ? name->asString() : "";
      auto it = std::find_if(merged.begin(), merged.end(), [&](const Json& m) {
        const Json* n = m.find("scenario");
        return (n ? n->asString() : "") == key;
      });
      if (it != merged.end())
        *it = entry;
      else
        merged.push_back(entry);
    }
  }
  return summaryDocument(merged);
}

Json readSummaryFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    return Json::parse(ss.str());
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
}

double paperTableCm(const std::string& scenario) {
  // Paper Table I: rows Open / Narrow, columns Minimally Contributing / Facilitating.
  static const std::pair<const char*, double> kTable[] = {{"open_minimal", 0.15},
                                                          {"open_facilitating", 0.94},
                                                          {"narrow_minimal", 0.05},
                                                          {"narrow_facilitating", 0.49}};
  for (const auto& [name, cm] : kTable)
    if (scenario.rfind(name, 0) == 0) return cm;
  return std::nan("");
}

std::string formatCmTable(const Json& summary) {
  const Json* list = summary.find("scenarios");
  if (!list || list->type() != Json::Type::kArray)
    throw std::runtime_error("not a coopnav summary (no \"scenarios\" array)");

  // Table I order first (open then narrow; facilitating then minimal as issue 6 lists them).
  static const char* const kOrder[] = {"open_facilitating", "open_minimal", "narrow_facilitating",
                                       "narrow_minimal"};
  std::vector<const Json*> rows;
  for (const char* name : kOrder)
    for (const auto& e : list->items())
      if (const Json* n = e.find("scenario"); n && n->asString().rfind(name, 0) == 0)
        rows.push_back(&e);
  for (const auto& e : list->items())
    if (std::find(rows.begin(), rows.end(), &e) == rows.end()) rows.push_back(&e);

  auto boolText = [](const Json* j) {
    if (!j || j->isNull()) return std::string("-");
    return std::string(j->asBool() ? "yes" : "no");
  };
  auto predText = [](const Json* j) {
    if (!j || j->isNull()) return std::string("UNKNOWN");
    return std::string(j->asBool() ? "TRUE" : "FALSE");
  };
  auto num = [](const Json* j) { return fixed(j ? j->asNumber() : std::nan(""), 2); };

  std::string out =
      "CM [m]: ours = interaction CM (round 1 to crossing, no reset), as Table I reports it;\n"
      "window = CM since the last reset (round 2 decides on it). Paper = Table I (gamma 0.98).\n";
  char buf[512];
  std::snprintf(buf, sizeof buf, "%-24s %5s %8s %9s %9s %-15s %-6s %-9s %s\n", "scenario", "human",
                "CM ours", "CM paper", "CM window", "IsContributing", "docked", "collision",
                "final state");
  out += buf;
  for (const Json* e : rows) {
    const Json* n = e->find("scenario");
    const std::string name = n ? n->asString() : "";
    const Json* humans = e->find("humans");
    const std::string paper = fixed(paperTableCm(name), 2);
    const Json* final_state = e->find("final_state");
    const std::string state = final_state && !final_state->isNull() ? final_state->asString() : "-";
    if (!humans || humans->items().empty()) {
      std::snprintf(buf, sizeof buf, "%-24s %5s %8s %9s %9s %-15s %-6s %-9s %s\n", name.c_str(),
                    "-", "-", paper.c_str(), "-", "-", boolText(e->find("docked")).c_str(),
                    boolText(e->find("collision")).c_str(), state.c_str());
      out += buf;
      continue;
    }
    for (const auto& h : humans->items()) {
      const Json* id = h.find("id");
      const std::string id_text = id ? jsonNumber(id->asNumber()) : "-";
      std::snprintf(buf, sizeof buf, "%-24s %5s %8s %9s %9s %-15s %-6s %-9s %s\n", name.c_str(),
                    id_text.c_str(), num(h.find("cm_interaction_m")).c_str(), paper.c_str(),
                    num(h.find("cm_window_m")).c_str(),
                    predText(h.find("is_contributing_interaction")).c_str(),
                    boolText(h.find("docked")).c_str(), boolText(e->find("collision")).c_str(),
                    state.c_str());
      out += buf;
    }
  }
  return out;
}

}  // namespace coopnav::ctl
