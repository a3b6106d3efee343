#include <map>
#include <sstream>
#include <tuple>

#include "laserfit/bench/runner.hpp"
#include "laserfit/metrics/stats.hpp"

namespace laserfit::bench {

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
  o << "method,scene,object,records,success_rate,false_accepts,ambiguous,failed,t_err_um_median,t_err_um_p95,"
       "r_err_deg_median,r_err_deg_p95,time_s_median,time_s_p95,peak_rss_mb_max\n";
  for (const auto& [key, rs] : groups) {
    std::vector<double> t, r, time;
    double peak = 0;
    int ok = 0, fa = 0, amb = 0, failed = 0;
    for (const auto* x : rs) {
      ok += x->at("success").get<bool>(), fa += x->at("false_accept").get<bool>();
      const std::string st = x->at("status");
      amb += st == "ambiguous", failed += st == "failed";
      if (st != "failed" && x->at("expect") == "pose") {
        t.push_back(x->at("t_err_um")), r.push_back(x->at("r_err_deg"));
      }
      time.push_back(x->at("timing").at("time_s"));
      peak = std::max(peak, x->at("timing").at("peak_rss_mb").get<double>());
    }
    const auto& [m, scene, object] = key;
    o << m << ',' << scene << ',' << object << ',' << rs.size() << ',' << double(ok) / rs.size() << ',' << fa << ','
      << amb << ',' << failed << ',' << metrics::median(t) << ',' << metrics::quantile(t, 0.95) << ','
      << metrics::median(r) << ',' << metrics::quantile(r, 0.95) << ',' << metrics::median(time) << ','
      << metrics::quantile(time, 0.95) << ',' << peak << '\n';
  }
  return o.str();
}

}  // namespace laserfit::bench
