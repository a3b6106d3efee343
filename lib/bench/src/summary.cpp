#include <map>
#include <sstream>
#include <tuple>

#include "laserfit/bench/runner.hpp"
#include "laserfit/metrics/stats.hpp"

namespace laserfit::bench {

GroupStats group_stats(const std::vector<const io::Json*>& rs) {
  GroupStats g;
  std::vector<double> t, r, time;
  for (const auto* x : rs) {
    ++g.records;
    g.successes += x->at("success").get<bool>(),
        g.false_accepts += x->at("false_accept").get<bool>();
    const std::string st = x->at("status");
    g.ambiguous += st == "ambiguous", g.failed += st == "failed";
    // visible_points is absent in results of older runs
    g.not_visible += !x->at("success").get<bool>() && !in_view(x->value("visible_points", -1L));
    if (determinable(*x))
      ++g.determinable, g.determinable_successes += x->at("success").get<bool>();
    if (st != "failed" && x->at("expect") == "pose")
      t.push_back(x->at("t_err_um")), r.push_back(x->at("r_err_deg"));
    time.push_back(x->at("timing").at("time_s"));
    g.peak_rss_mb = std::max(g.peak_rss_mb, x->at("timing").at("peak_rss_mb").get<double>());
  }
  g.t_median_um = metrics::median(t), g.t_p95_um = metrics::quantile(t, 0.95);
  g.r_median_deg = metrics::median(r), g.r_p95_deg = metrics::quantile(r, 0.95);
  g.time_median_s = metrics::median(time), g.time_p95_s = metrics::quantile(time, 0.95);
  return g;
}

size_t share_scan_facts(std::vector<io::Json>& records) {
  using Key = std::tuple<std::string, int, std::string>;
  auto key = [](const io::Json& r) {
    return Key{r.value("benchmark", ""), r.at("trial").get<int>(),
               r.at("object").get<std::string>()};
  };
  std::map<Key, const io::Json*> donor;
  for (const auto& r : records)
    if (r.contains("determinable") && r.contains("visible_points")) donor.emplace(key(r), &r);
  size_t filled = 0;
  for (auto& r : records) {
    if (r.contains("determinable") || r.contains("visible_points")) continue;
    const auto it = donor.find(key(r));
    if (it == donor.end()) continue;
    r["determinable"] = it->second->at("determinable");
    r["visible_points"] = it->second->at("visible_points");
    r["scan_facts_from"] = it->second->at("method");
    ++filled;
  }
  return filled;
}

std::string summary_csv(const std::vector<io::Json>& records) {
  using Key = std::tuple<std::string, std::string, std::string>;
  std::map<Key, std::vector<const io::Json*>> groups;
  for (const auto& r : records) {
    const std::string m = r.at("method");
    groups[{m, r.at("scene"), r.at("object")}].push_back(&r);
    groups[{m, "all", "all"}].push_back(&r);
  }
  std::ostringstream o;
  o.precision(6);
  o << "method,scene,object,records,success_rate,false_accepts,ambiguous,failed,t_err_um_median,t_"
       "err_um_p95,"
       "r_err_deg_median,r_err_deg_p95,time_s_median,time_s_p95,peak_rss_mb_max,not_visible,"
       "determinable,determinable_success_rate\n";
  for (const auto& [key, rs] : groups) {
    const GroupStats g = group_stats(rs);
    const auto& [m, scene, object] = key;
    o << m << ',' << scene << ',' << object << ',' << g.records << ',' << g.success_rate() << ','
      << g.false_accepts << ',' << g.ambiguous << ',' << g.failed << ',' << g.t_median_um << ','
      << g.t_p95_um << ',' << g.r_median_deg << ',' << g.r_p95_deg << ',' << g.time_median_s << ','
      << g.time_p95_s << ',' << g.peak_rss_mb << ',' << g.not_visible << ',' << g.determinable
      << ',' << g.determinable_success_rate() << '\n';
  }
  return o.str();
}

}  // namespace laserfit::bench
