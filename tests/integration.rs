//! The integration tests of `tyreroad`, one test binary: each file of
//! this folder is a module of it, so that the dependencies' generic code
//! is instantiated and linked once rather than once per file (most of CI's
//! time is compiling). Run one file with
//! `cargo test -p tyreroad --test integration <file>::`.

mod common;

mod calibrate_along_slope;
mod calibrate_under_tread;
mod clusters;
mod deformed_slope_tiles;
mod distributed_interaction;
mod fidelity;
mod fidelity_fields;
mod fidelity_rolling;
mod fidelity_rolling_fields;
mod layers;
mod output_swap;
mod pressed_through;
mod refusals;
mod road_kinds;
mod rolling_off_road;
mod scenario_fuzz;
mod split_wide_tops;
mod static_failures;
mod texture_rolling;
mod texture_rolling_road;
mod texture_windows;
mod texture_without_asperity;
mod tidy;
mod two_scale;
mod two_scale_neighbours;
mod visco_bad_input;
mod visco_bem_fixture;
mod visco_calibrated;
mod visco_calibrated_fields;
