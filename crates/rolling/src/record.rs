//! What a rolling run returns: one record per step and the signals drawn
//! from them.

pub use tyreroad_multipoint::Recovery;

/// How a step's solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepStatus {
    /// The solver met its tolerance.
    Converged,
    /// The solver stagnated just above the tolerance, within its acceptable
    /// tolerance (`tyreroad_multipoint::Convergence::Stagnated`), or the
    /// deformed tread's slopes were held a round short of their fixed
    /// point; the step's values are kept, its residual saying by how much.
    Stagnated,
    /// The solve failed after every recovery: the step's force, approach,
    /// area and sensor values are NaN and it has no contacts; the next step
    /// cold-starts and the run goes on.
    Failed,
}

impl StepStatus {
    /// The lower-case name written in `time_signals.csv` and checkpoints.
    pub fn name(self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::Stagnated => "stagnated",
            Self::Failed => "failed",
        }
    }
}

/// The lower-case name of a recovery, as written in `time_signals.csv`.
pub fn recovery_name(recovery: Recovery) -> &'static str {
    match recovery {
        Recovery::None => "none",
        Recovery::Continuation => "continuation",
        Recovery::ColdRestart => "cold_restart",
        Recovery::DenseFallback => "dense_fallback",
        Recovery::Regularized => "regularized",
        Recovery::Clustered => "clustered",
        Recovery::ProfileSlope => "profile_slope",
    }
}

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
    /// Approach `δ0` of the tread below the road's reference plane
    /// ([`crate::Road::top`]) (m).
    pub approach: f64,
    /// Contact area `Σ π a_i²` of the local contacts (m²).
    pub contact_area: f64,
    /// Asperities in contact.
    pub contacts: usize,
    /// Asperities selected under the footprint (problem size).
    pub selected: usize,
    /// Newton iterations spent (for a failed step, those of the failed
    /// solve).
    pub iterations: usize,
    /// How the step's solve ended. A [`StepStatus::Failed`] step has NaN
    /// `total_force`, `approach`, `contact_area`, `clearance` and sensor
    /// forces, and no contacts.
    pub status: StepStatus,
    /// The solver's attempt that produced the step ([`Recovery::None`] for
    /// a step with nothing to solve and for a failed step).
    pub recovery: Recovery,
    /// Largest force residual relative to the force scale (for a failed
    /// step, the best one reached; 0 when there was nothing to solve).
    pub residual: f64,
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
    /// The smallest truncation clearance over the run (m), failed steps
    /// left out; see [`StepRecord::clearance`].
    pub fn min_clearance(&self) -> f64 {
        self.steps
            .iter()
            .filter(|s| s.status != StepStatus::Failed)
            .map(|s| s.clearance)
            .fold(f64::INFINITY, f64::min)
    }
    /// Steps per status: `[converged, stagnated, failed]`.
    pub fn status_counts(&self) -> [usize; 3] {
        let mut n = [0; 3];
        for s in &self.steps {
            n[match s.status {
                StepStatus::Converged => 0,
                StepStatus::Stagnated => 1,
                StepStatus::Failed => 2,
            }] += 1;
        }
        n
    }
    /// Whether every step converged (what `--strict` demands).
    pub fn all_converged(&self) -> bool {
        self.steps.iter().all(|s| s.status == StepStatus::Converged)
    }
}

/// A signal with its failed samples (NaN) replaced by linear interpolation
/// between the nearest good samples (held constant beyond the first or last
/// good one), and how many were replaced; for spectra, which need every
/// sample. All zero when no sample is finite.
pub fn interpolate_failed(signal: &[f64]) -> (Vec<f64>, usize) {
    let mut out = signal.to_vec();
    let good: Vec<usize> = (0..out.len()).filter(|&i| out[i].is_finite()).collect();
    let replaced = out.len() - good.len();
    if replaced == 0 {
        return (out, 0);
    }
    let (Some(&first), Some(&last)) = (good.first(), good.last()) else {
        return (vec![0.0; out.len()], replaced);
    };
    for i in 0..out.len() {
        if out[i].is_finite() {
            continue;
        }
        out[i] = if i < first {
            signal[first]
        } else if i > last {
            signal[last]
        } else {
            // The good neighbours on each side.
            let right = good[good.partition_point(|&g| g < i)];
            let left = good[good.partition_point(|&g| g < i) - 1];
            let t = (i - left) as f64 / (right - left) as f64;
            signal[left] + t * (signal[right] - signal[left])
        };
    }
    (out, replaced)
}

#[cfg(test)]
mod tests {
    use super::interpolate_failed;

    #[test]
    fn failed_samples_are_bridged_linearly_and_counted() {
        let nan = f64::NAN;
        let (s, n) = interpolate_failed(&[nan, 1.0, nan, nan, 4.0, nan]);
        assert_eq!((s, n), (vec![1.0, 1.0, 2.0, 3.0, 4.0, 4.0], 4));
        let (s, n) = interpolate_failed(&[1.0, 2.0]);
        assert_eq!((s, n), (vec![1.0, 2.0], 0));
        let (s, n) = interpolate_failed(&[nan, nan]);
        assert_eq!((s, n), (vec![0.0, 0.0], 2));
    }
}
