//! Test maps shared by the integration tests (a test file takes them with
//! `use crate::common;`).

use tyreroad::contact_law::Material;
use tyreroad::fidelity::rolling::{calibrate_rolling_road_under, calibrated_rolling_road};
use tyreroad::fidelity::table_depth::TablePlan;
use tyreroad::fidelity::under_tread::CalibrateUnder;
use tyreroad::fidelity::{CalibratedLaw, CalibrationOptions, Calibrator};
use tyreroad::rolling::{Road, RollingConfig};
use tyreroad::shared::Par;
use tyreroad::texture::HeightMap;
use tyreroad::texture_road::{TextureRoadOptions, rolling_road, texture_road};

/// Three ridges along y whose summits sit at alternate ends: cross-section
/// radius 4 mm, ends rounded to 2 mm, each tilted by `tilt` (±, alternating)
/// along its length, summits 0, 10 and 20 µm apart in height, the map
/// clipped at `floor` below the top. The fidelity tests' case where a cap's
/// contact runs along it and a flat punch meets it at one end.
pub struct TiltedRidges {
    /// Grid points along x and y.
    pub size: (usize, usize),
    /// Cell size (m).
    pub cell: f64,
    /// The ridges' x positions (m).
    pub x: [f64; 3],
    /// Tilt along the ridge (m/m).
    pub tilt: f64,
    /// Half the straight length (m).
    pub half_length: f64,
    /// The ridges' mid-length y (m).
    pub y_centre: f64,
    /// Height of the clipping plane (m, below 0).
    pub floor: f64,
}

impl TiltedRidges {
    /// The height map.
    pub fn map(&self) -> HeightMap {
        let (rx, rend, half, yc) = (4e-3, 2e-3, self.half_length, self.y_centre);
        let ridges = [
            (self.x[0], self.tilt, 0.0),
            (self.x[1], -self.tilt, 10e-6),
            (self.x[2], self.tilt, 20e-6),
        ];
        let floor = self.floor;
        HeightMap::from_fn(
            self.size.0,
            self.size.1,
            self.cell,
            self.cell,
            move |x, y| {
                ridges
                    .iter()
                    .map(|&(xk, slope, drop)| {
                        let along = (y - yc).abs() - half;
                        let end = if along > 0.0 {
                            along * along / (2.0 * rend)
                        } else {
                            0.0
                        };
                        -(x - xk).powi(2) / (2.0 * rx) - slope * (y - yc) - end - drop
                    })
                    .fold(floor, f64::max)
            },
        )
        .expect("a valid ridge map")
    }
}

/// The rolling tests' ridges: 6 mm apart, 10 mm long, tilted ±3 µm/mm,
/// clipped 1.2 mm below the top, 30 × 20 mm at 0.2 mm.
#[allow(
    dead_code,
    reason = "each test file that includes this module uses part of it"
)]
pub fn rolling_ridges() -> HeightMap {
    TiltedRidges {
        size: (151, 101),
        cell: 2e-4,
        x: [9e-3, 15e-3, 21e-3],
        tilt: 3e-3,
        half_length: 5e-3,
        y_centre: 10e-3,
        floor: -1.2e-3,
    }
    .map()
}

/// The calibrated rolling road of `map` (with fields, on `m`), each cap
/// under `under`, as a scenario builds it (y centred on the map's middle,
/// summit radii, laws placed along the path when calibrated so), and the
/// largest approach its tables cover (m).
#[allow(
    dead_code,
    reason = "each test file that includes this module uses part of it"
)]
pub fn calibrated_road(
    map: &HeightMap,
    m: Material,
    config: &RollingConfig,
    under: CalibrateUnder,
) -> (Road<CalibratedLaw>, f64) {
    let troad = texture_road(map, m, &TextureRoadOptions::new(0.2e-3, 2e-6)).expect("texture road");
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let radii = troad.summit_radii();
    let set = troad.set.clone().translated([0.0, -y_mid]).expect("frame");
    let wilke = rolling_road(set, radii.clone(), troad.top).expect("radii");
    let calibrator = Calibrator::new(m, CalibrationOptions::default()).with_fields();
    let cal = calibrate_rolling_road_under(
        &troad,
        &wilke,
        map,
        config,
        &calibrator,
        Par::Seq,
        &TablePlan::new(under),
    )
    .expect("calibration");
    let radii = cal.kept.iter().map(|&i| radii[i]).collect();
    (
        calibrated_rolling_road(cal.set, radii, troad.top).expect("road"),
        cal.max_approach,
    )
}

/// The load of a [`tiled_road`] (N).
pub const TILED_LOAD: f64 = 1500.0;

/// The tread of a [`tiled_road`]: the fixtures' elastic rubber.
pub const TREAD_RUBBER: &str = "[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n";

/// A rolling scenario: a tyre at [`TILED_LOAD`] and 50 km/h on the
/// chip-seal fixture's grid (`nx` columns, 600 rows, 0.25 mm) of road
/// `kind` with its tops split into 5 mm tiles, from `path.0` to `path.1`
/// in 1 mm steps, rung `fidelity`, `[rolling] contact_slope = slope`, tread
/// [`TREAD_RUBBER`]. The tests of wide tops split into tiles take it and
/// change what they measure by replacing its lines.
pub fn tiled_road(
    kind: &str,
    nx: usize,
    path: (&str, &str),
    fidelity: &str,
    slope: &str,
) -> String {
    let (start, end) = path;
    format!(
        "name = \"tiles\"\n{TREAD_RUBBER}\
         [model]\nfidelity = \"{fidelity}\"\n\
         [rolling]\nstart = \"{start}\"\nend = \"{end}\"\nstep = \"1 mm\"\nspeed = \"50 km/h\"\n\
         margin = \"0 mm\"\nreference_force = \"1 N\"\ncheckpoint = false\n\
         contact_slope = \"{slope}\"\n\
         [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\n\
         length = \"120 mm\"\nwidth = \"150 mm\"\n\
         [rolling.control]\nload = \"{TILED_LOAD} N\"\n\
         [texture]\nmin_prominence = \"0.1 mm\"\nmin_area = \"1 mm2\"\nmax_cap_width = \"5 mm\"\n\
         [texture.synth]\nkind = \"{kind}\"\nnx = {nx}\nny = 600\nspacing = \"0.25 mm\"\n\
         seed = 2006\n"
    )
}

/// `road` (a [`tiled_road`]) with its caps calibrated under the tread
/// (`[model] calibrate_under = "tread"`).
pub fn under_tread(road: &str) -> String {
    road.replace("[model]\n", "[model]\ncalibrate_under = \"tread\"\n")
}
