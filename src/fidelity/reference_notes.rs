//! What a comparison with the BEM cannot say, said beside its rows: a
//! table of small errors is no validation when the reference itself is
//! made up of filled points, presses the whole road flat, or resolves the
//! contact on a handful of cells.

use crate::texture::HeightMap;

use super::compare::BemLoad;

/// Share of the map's points that may be missing (filled for the BEM)
/// before the reference is said to be partly made up.
const MISSING_SHARE: f64 = 0.05;
/// Share of a load the BEM may carry on filled points before it is said.
const LOAD_ON_MISSING: f64 = 0.05;
/// Share of the map the BEM's contact may cover before the road is said to
/// be pressed flat.
const PRESSED_FLAT: f64 = 0.5;
/// Fewest cells of a resolved BEM contact.
const RESOLVED_CELLS: f64 = 20.0;

/// The notes of a comparison on `map` with `asperities` kept, against the
/// BEM loads `bem`: missing points filled (and the load they carry), a
/// contact covering most of the map, a contact of too few cells, a single
/// asperity. Empty when the reference is a road's.
pub fn reference_notes(map: &HeightMap, asperities: usize, bem: &[BemLoad]) -> Vec<String> {
    let mut notes = Vec::new();
    let points = map.nx() * map.ny();
    let missing = points - map.valid_count();
    let missing_share = missing as f64 / points as f64;
    if missing_share > MISSING_SHARE {
        notes.push(format!(
            "{missing} of the map's {points} points ({:.1} %) are missing: the BEM fills them \
             from their neighbours, so part of its road is made up",
            100.0 * missing_share
        ));
    }
    if asperities == 1 {
        notes.push(
            "one asperity kept: min_prominence and min_area keep no other summit, so the \
             comparison is of one cap's law, not of a texture's load sharing"
                .into(),
        );
    }
    let map_area = points as f64 * map.dx() * map.dy();
    let cell = map.dx() * map.dy();
    for b in bem {
        if b.on_missing > LOAD_ON_MISSING * b.load {
            notes.push(format!(
                "at {} N the BEM carries {:.1} % of the load on missing points, filled: that \
                 share of the reference is no measured road",
                b.load,
                100.0 * b.on_missing / b.load
            ));
        }
        if b.contact_area > PRESSED_FLAT * map_area {
            notes.push(format!(
                "at {} N the BEM's contact covers {:.0} % of the map: the road is pressed flat, \
                 and the comparison says little of its texture (a lighter load, a stiffer \
                 material or a larger map)",
                b.load,
                100.0 * b.contact_area / map_area
            ));
        }
        let cells = b.contact_area / cell;
        if cells < RESOLVED_CELLS {
            notes.push(format!(
                "at {} N the BEM's contact is {cells:.0} cell(s): too few to resolve it, so \
                 neither side's figures mean much (a heavier load or a finer map)",
                b.load
            ));
        }
    }
    notes
}
