//! Virtual force sensors: rectangles fixed on the road that integrate each
//! local contact's pressure.

use std::sync::OnceLock;

use tyreroad_contact_law::{LocalContact, PressureProfile};

/// A virtual force sensor: a rectangle fixed on the road, like one pressure
/// cell of a road-embedded array. Its force is the part of each local
/// contact's pressure that falls inside it ([`Sensor::share`]): a contact
/// straddling the sensor's edge is split, so the signal does not jump when a
/// summit crosses the edge.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensor {
    /// Name (CSV column).
    pub name: String,
    /// `[x0, x1]` (m).
    pub x: [f64; 2],
    /// `[y0, y1]` (m).
    pub y: [f64; 2],
}

impl Sensor {
    /// Whether the point `(x, y)` lies inside the rectangle (edges included).
    pub fn contains(&self, [x, y]: [f64; 2]) -> bool {
        (self.x[0]..=self.x[1]).contains(&x) && (self.y[0]..=self.y[1]).contains(&y)
    }

    /// The part (N) of a local contact's force that the sensor sees: the
    /// contact's axisymmetric pressure (its profile and radius, centred on
    /// the summit `centre`) integrated over the rectangle.
    ///
    /// A contact wholly inside gives its whole force, one wholly outside 0.
    /// One that straddles an edge is integrated by an equal-force rule:
    /// [`SHARE_RINGS`] rings, each carrying the same force (radii from the
    /// profile's cumulative force), times [`SHARE_SPOKES`] spokes, each
    /// sample counted in the half-open rectangle `[x0, x1) × [y0, y1)` so
    /// that sensors tiling the road share a contact exactly. A straight
    /// edge through the centre gives exactly half, a corner a quarter.
    pub fn share(&self, centre: [f64; 2], contact: &LocalContact) -> f64 {
        let p = contact.force;
        let a = contact.radius;
        if !(p > 0.0) {
            return 0.0;
        }
        let [cx, cy] = centre;
        let inside =
            |x: f64, y: f64| self.x[0] <= x && x < self.x[1] && self.y[0] <= y && y < self.y[1];
        if !(a > 0.0) {
            return if inside(cx, cy) { p } else { 0.0 };
        }
        if cx - a >= self.x[0] && cx + a < self.x[1] && cy - a >= self.y[0] && cy + a < self.y[1] {
            return p;
        }
        if cx + a < self.x[0] || cx - a >= self.x[1] || cy + a < self.y[0] || cy - a >= self.y[1] {
            return 0.0;
        }
        let rings = ring_radii(contact.profile);
        let mut count = 0usize;
        for &rho in rings.iter() {
            for m in 0..SHARE_SPOKES {
                let phi = (m as f64 + 0.5) * std::f64::consts::TAU / SHARE_SPOKES as f64;
                if inside(cx + a * rho * phi.cos(), cy + a * rho * phi.sin()) {
                    count += 1;
                }
            }
        }
        p * count as f64 / (SHARE_RINGS * SHARE_SPOKES) as f64
    }
}

impl Sensor {
    /// The part (N) of a contact's `force` that the sensor sees when the
    /// force is spread as `spread` around `centre` (the contact point): each
    /// point's weight uniform over its square, counted with the fraction of
    /// the square inside the rectangle. Sensors tiling the road share the
    /// force exactly (their fractions sum to one).
    pub fn share_spread(&self, centre: [f64; 2], force: f64, spread: &crate::Spread) -> f64 {
        if !(force > 0.0) {
            return 0.0;
        }
        let half = 0.5 * spread.cell;
        let fraction = |c: f64, [a, b]: [f64; 2]| {
            if half > 0.0 {
                ((c + half).min(b) - (c - half).max(a)).max(0.0) / spread.cell
            } else if a <= c && c < b {
                1.0
            } else {
                0.0
            }
        };
        force
            * spread
                .points
                .iter()
                .map(|(p, w)| {
                    w * fraction(centre[0] + p[0], self.x) * fraction(centre[1] + p[1], self.y)
                })
                .sum::<f64>()
    }
}

/// Rings of the equal-force rule of [`Sensor::share`].
pub const SHARE_RINGS: usize = 24;
/// Spokes of the equal-force rule of [`Sensor::share`] (a multiple of 4, so
/// the rule is symmetric about both axes and no sample lies on them).
pub const SHARE_SPOKES: usize = 48;

/// Ring radii `ρ_k / a` of the equal-force rule: the cumulative force
/// `F(ρ)/P` at the ring's midpoint `(k + ½)/K`, for each profile.
fn ring_radii(profile: PressureProfile) -> &'static [f64; SHARE_RINGS] {
    static HERTZ: OnceLock<[f64; SHARE_RINGS]> = OnceLock::new();
    static CONE: OnceLock<[f64; SHARE_RINGS]> = OnceLock::new();
    let (cell, cumulative): (_, fn(f64) -> f64) = match profile {
        // ∫ 3/(2πa²)·√(1 − r²/a²) over r < ρ = 1 − (1 − ρ²)^{3/2}.
        PressureProfile::Hertz => (&HERTZ, |r: f64| 1.0 - (1.0 - r * r).powf(1.5)),
        // ∫ 1/(πa²)·arcosh(a/r) over r < ρ = ρ² arcosh(1/ρ) + 1 − √(1 − ρ²).
        PressureProfile::Cone => (&CONE, |r: f64| {
            if r <= 0.0 {
                0.0
            } else {
                r * r * (1.0 / r).acosh() + 1.0 - (1.0 - r * r).sqrt()
            }
        }),
    };
    cell.get_or_init(|| {
        std::array::from_fn(|k| {
            let target = (k as f64 + 0.5) / SHARE_RINGS as f64;
            // The cumulative force increases from 0 to 1 on [0, 1]: bisect.
            let (mut lo, mut hi) = (0.0f64, 1.0f64);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if cumulative(mid) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        })
    })
}
