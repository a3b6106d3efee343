// An outcome as one JSON Lines record (the campaign files, `sim --out` and `run -o`).
#include "laserfit/controller/sim.hpp"

namespace laserfit::controller {

io::Json outcome_json(const Outcome& o) {
  return {{"strategy", name_of(o.strategy)},
          {"setting", o.setting},
          {"start", o.start + 1},
          {"seed", o.seed},
          {"success", o.success},
          {"result", o.result},
          {"lateral_um", {o.insertion.x_mm * 1e3, o.insertion.y_mm * 1e3}},
          {"angle_deg", o.insertion.angle_deg},
          {"depth_um", o.insertion.depth_mm * 1e3},
          {"scans", o.scans},
          {"rounds", o.rounds},
          {"time_s", o.time_s},
          {"cell_time_s", o.cell_time_s},
          {"compute_s", o.compute_s},
          {"completion_s", o.completion_s},
          {"cell_fault", o.cell_fault},
          {"log", o.log}};
}

}  // namespace laserfit::controller
