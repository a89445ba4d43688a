// MossScenario: the deck keys (the scenario itself is in moss_scenario.cpp).
#include "scenarios/moss_scenario.hpp"

namespace biota::scenarios {

void MossScenario::declare_config(core::ConfigSchema& s) {
  s.add_string("moss.terrain.file", "moss/scene.obj", {},
               "terrain OBJ (with its MTL and texture); a relative path is relative to the deck");
  s.add_string("moss.terrain.up", "y", {"y", "z"}, "up axis of the OBJ (z: turned into y-up)");
  s.add_real("moss.terrain.colour_tolerance", 0.1, 0.0, 1.8, "-",
             "largest RGB distance (in [0, 1] units) of a texture colour from its soil colour");
  s.add_real_list("moss.soil.reflectance", std::vector<double>{0.2, 0.35, 0.2}, 3, "-",
                  "photon reflectance of humus, sand, asphalt (erratum 3: not in the paper)");
  s.add_string("moss.soil.delta_form", "corrected", {"corrected", "printed"},
               "(3.15): the corrected dq_SAT/dT or the paper's formula read literally (erratum 6)");
  s.add_real("moss.soil.ch_radius", 0.1, 0.0, 1.0, "m",
             "(3.5): mosses counted within this radius of a face centroid (erratum 14)", true);
  s.add_real("moss.light.open_insolation", 100.0, 0.0, 2000.0, "W/m^2",
             "S_open: what open horizontal ground receives (photon power calibration, erratum 2)");
  s.add_int("moss.light.photons", 8192, 1, 100'000'000, "photons emitted per day (paper: 8192)");
  s.add_real("moss.light.radius", 0.1, 0.0, 1.0, "m", "photon count radius r of S", true);
  s.add_bool("moss.light.indirect", true,
             "diffuse interreflection (false: photons stored at their first hit only, exp. 1)");
  s.add_real("moss.light.distance_factor", 20.0, 1.5, 1e6, "-",
             "light at this many bounding radii from the scene centre (erratum 4)");
  s.add_string("moss.sun.mode", "zenith", {"zenith", "angles", "date"},
               "sun position: zenith (Table 4.3 incidence 90 deg), elevation/azimuth, or date");
  s.add_real("moss.sun.elevation", 90.0, 0.0, 90.0, "deg", "elevation (mode angles)", true);
  s.add_real("moss.sun.azimuth", 180.0, 0.0, 360.0, "deg",
             "azimuth from north (-z) towards east (+x) (mode angles)");
  s.add_int("moss.sun.day_of_year", 172, 1, 365, "day of year (mode date)");
  s.add_real("moss.sun.hour", 12.0, 0.0, 24.0, "h", "solar hour, 12 = noon (mode date)");
  s.add_real("moss.sun.latitude", 35.0, -90.0, 90.0, "deg", "latitude (mode date)");
  s.add_real("moss.weather.temperature", 288.15, 200.0, 350.0, "K", "air temperature T");
  s.add_real("moss.weather.humidity", 0.73, 0.0, 1.0, "-", "relative humidity rh");
  s.add_real("moss.weather.precipitation", 1861.2, 0.0, 100000.0, "mm/year",
             "annual precipitation P");
  s.add_int("moss.weather.rain_days", 180, 0, 365,
            "rain days per year, evenly spaced, P / rain_days each (erratum 11)");
  s.add_real("moss.weather.wind", 0.2, 0.0, 100.0, "m/s", "wind speed U", true);
  s.add_real("moss.weather.possible_sunshine", 8.0, 0.0, 24.0, "h", "N0", true);
  s.add_real("moss.weather.sunshine", 6.0, 0.0, 24.0, "h", "N (sunshine ratio A = N / N0)");
  for (int k = 0; k < 3; ++k) s.add_bool(kSpeciesKeys[k], true, "species of Table 4.2 present");
  s.add_int("moss.initial", 256, 0, 16384, "mosses placed at random on upward faces at day 0");
  s.add_int("moss.max_mosses", 16384, 1, 10'000'000,
            "cap on live mosses (paper: 16384); at the cap germination is refused (erratum 29)");
  s.add_int("moss.max_seeds", 65536, 0, 10'000'000,
            "cap on dormant seeds; new seeds beyond it are dropped (counted)");
  s.add_int("moss.max_layers", 3, 1, 1000,
            "models per column: a seed landing on a moss of the top layer rolls off (is lost)");
  s.add_real("moss.size", 0.01, 0.0, 0.5, "m", "edge of a moss model (paper: 1 cm)", true);
  s.add_real("moss.reflectance", 0.2, 0.0, 1.0, "-", "photon reflectance of a moss model");
  s.add_real("moss.gemma_distance", 0.02, 0.0, 1.0, "m", "k of (3.22)", true);
  s.add_real("moss.spore_distance", 0.05, 0.0, 5.0, "m", "l of (3.23)", true);
  s.add_real("moss.patch.radius", 0.015, 0.0, 0.5, "m",
             "surface-of-patch test: neighbours counted within this radius (ghost cutoff)", true);
  s.add_int("moss.patch.inside", 8, 1, 1000,
            "a moss with at least this many neighbours is inside its patch: it does not reproduce");
  s.add_int("moss.outside_spore_interval", 10, 0, 100000,
            "days between spores arriving from outside (0: none)");
  s.add_real("moss.noise.amplitude", 0.005, 0.0, 1.0, "m",
             "RMS horizontal 1/f (fBm) displacement of growth positions");
  s.add_real("moss.noise.hurst", 0.3, 0.01, 0.99, "-", "Hurst exponent of the fBm fields");
  s.add_int("moss.noise.levels", 8, 1, 12, "fBm fields of (2^levels + 1)^2 points over the scene");
  s.add_real("moss.region.back_z", 0.7, -1e6, 1e6, "m",
             "CSV region 'back' (under the roof and the back floor): z below this");
  s.add_real("moss.region.roof_y", 1.0, -1e6, 1e6, "m", "CSV region 'roof': y above this");
}

}  // namespace biota::scenarios
