#include "trainer/tension_law_file.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include "trainer/strict_json.h"

namespace colosim {

namespace {
constexpr const char* kFormat = "colosim-tension-law v1";
}

nlohmann::json tensionLawJson(const ExtendedLawParams& p, const std::vector<double>& sd, const std::string& source) {
  const ExtendedTensionLaw law(p);
  nlohmann::json params = nlohmann::json::object();
  const std::vector<LawParameter> lp = law.parameters();
  for (size_t i = 0; i < lp.size(); ++i) {
    nlohmann::json q = {{"value", lp[i].value}, {"unit", lp[i].unit}};
    if (i < sd.size() && std::isfinite(sd[i])) q["sd"] = sd[i];
    params[lp[i].name] = q;
  }
  return {{"format", kFormat}, {"law", law.name()}, {"effects", p.effects()}, {"params", params}, {"source", source}};
}

void writeTensionLawFile(const std::string& path, const ExtendedLawParams& p, const std::vector<double>& sd,
                         const std::string& source) {
  const nlohmann::json j = tensionLawJson(p, sd, source);
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(path + ": cannot write the file");
  out << j.dump(2) << "\n";
  if (!out) throw std::runtime_error(path + ": cannot write the file");
}

ExtendedLawParams readTensionLawFile(const std::string& path) {
  return parseTensionLawFile(readTextFile(path), path);
}

ExtendedLawParams parseTensionLawFile(const std::string& text, const std::string& path) {
  const nlohmann::json j = parseJsonText(text, path);
  if (!j.is_object()) throw InputError(path + ": expected a JSON object");
  JsonObject top(j, path);
  return readTensionLawObject(top);
}

ExtendedLawParams readTensionLawObject(JsonObject& top) {
  top.choice("format", {kFormat});
  const std::string name = top.choice("law", {"voigt", "extended"});
  const nlohmann::json& eff = top.raw("effects");
  if (!eff.is_array()) top.fail("effects", "expected a list of effect names");
  ExtendedLawParams p;
  for (size_t i = 0; i < eff.size(); ++i) {
    if (!eff[i].is_string()) top.fail("effects", "expected a list of effect names");
    try {
      p.enable(eff[i].get<std::string>());
    } catch (const std::invalid_argument& e) {
      top.fail("effects[" + std::to_string(i) + "]", e.what());
    }
  }
  if ((name == "voigt") != p.effects().empty())
    top.fail("law", "must be 'voigt' exactly when 'effects' is empty");
  JsonObject params = top.object("params");
  if (params.has("relax_g2") || params.has("relax_tau2_s")) p.prony_terms = 2;
  if (params.has("set_yield_strain")) p.set_yield = true;
  if (params.has("set_ratchet")) p.set_ratcheting = true;
  if (params.has("fung_cap_strain")) p.fung_capped = true;
  // The parameters a law with these effects has (the defaults are valid placeholders).
  for (const LawParameter& q : ExtendedTensionLaw(p).parameters()) {
    JsonObject v = params.object(q.name);
    const double value = v.number("value", -1e12, 1e12);
    const std::string unit = v.string("unit");
    if (unit != q.unit) v.fail("unit", "must be '" + q.unit + "', got '" + unit + "'");
    if (v.has("sd")) v.number("sd", 0, 1e12);
    v.finish();
    p.set(q.name, value);
  }
  params.finish();
  top.ignore("source");
  top.ignore("note");
  top.finish();
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    top.fail("params", e.what());
  }
  return p;
}

std::shared_ptr<const TensionLaw> loadTensionLaw(const std::string& path) {
  return std::make_shared<ExtendedTensionLaw>(readTensionLawFile(path));
}

}  // namespace colosim
