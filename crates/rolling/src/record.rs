//! What a rolling run returns: one record per step and the signals drawn
//! from them.

/// The outputs of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRecord {
    /// Step index `k`.
    pub index: usize,
    /// Footprint centre `x_c` (m).
    pub position: f64,
    /// Time `t = x_c / V` (s).
    pub time: f64,
    /// Total contact force `Σ P_i` (N).
    pub total_force: f64,
    /// Approach `δ0` of the tread below the road's highest summit (m).
    pub approach: f64,
    /// Contact area `Σ π a_i²` of the local contacts (m²).
    pub contact_area: f64,
    /// Asperities in contact.
    pub contacts: usize,
    /// Asperities selected under the footprint (problem size).
    pub selected: usize,
    /// Newton iterations spent.
    pub iterations: usize,
    /// `s_boundary − δ0` (m): when positive, every asperity left out of the
    /// selection has a gap larger than the approach, so it would carry
    /// exactly zero and the truncation is exact. Infinite for a block.
    pub clearance: f64,
    /// Pairs of contacts whose patches overlap (radii sum over their
    /// spacing), where the model's point-force coupling does not hold
    /// (`tyreroad_multipoint::overlapping_contacts`).
    pub overlapping: usize,
    /// Force on each sensor (N), in the order of
    /// [`RollingConfig::sensors`](crate::RollingConfig::sensors).
    pub sensor_forces: Vec<f64>,
    /// Road ids (indices into [`Road::positions`](crate::Road::positions))
    /// of the asperities in contact, in the order they were selected (by x).
    /// Only those with `P > 0`: a footprint selects a few hundred
    /// asperities of which a fraction touch, and a run keeps every step.
    pub contact_ids: Vec<usize>,
    /// Force on each asperity of [`StepRecord::contact_ids`] (N), all `> 0`;
    /// summed in order they give [`StepRecord::total_force`] exactly.
    pub contact_forces: Vec<f64>,
}

/// The result of a rolling run: one record per step, in path order.
#[derive(Clone, Debug, PartialEq)]
pub struct RollingResult {
    /// One record per step.
    pub steps: Vec<StepRecord>,
    /// Sampling rate `V/Δx` (Hz).
    pub sample_rate: f64,
    /// Steps loaded from a checkpoint instead of computed.
    pub resumed: usize,
    /// Hash of the inputs keying the checkpoint.
    pub input_hash: u64,
}

impl RollingResult {
    /// Times `t_k` (s).
    pub fn times(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.time).collect()
    }
    /// Total force signal (N).
    pub fn total_force(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.total_force).collect()
    }
    /// Approach signal (m).
    pub fn approach(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.approach).collect()
    }
    /// Contact-area signal (m²).
    pub fn contact_area(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.contact_area).collect()
    }
    /// Force signal of sensor `k` (N).
    pub fn sensor(&self, k: usize) -> Vec<f64> {
        self.steps
            .iter()
            .map(|s| s.sensor_forces.get(k).copied().unwrap_or(0.0))
            .collect()
    }
    /// The contact forces of the whole run as COO triplets `(step, id,
    /// force)`: step `k` is the position in [`RollingResult::steps`], `id`
    /// the road's asperity id, `force` in N (only `P > 0`).
    pub fn contact_triplets(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.steps.iter().enumerate().flat_map(|(k, s)| {
            s.contact_ids
                .iter()
                .zip(&s.contact_forces)
                .map(move |(&id, &p)| (k, id, p))
        })
    }
    /// The smallest truncation clearance over the run (m); see
    /// [`StepRecord::clearance`].
    pub fn min_clearance(&self) -> f64 {
        self.steps
            .iter()
            .map(|s| s.clearance)
            .fold(f64::INFINITY, f64::min)
    }
}
