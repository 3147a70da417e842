//! The integration tests of `tyreroad-multipoint`, one test binary: each file of
//! this folder is a module of it, so that the dependencies' generic code
//! is instantiated and linked once rather than once per file (most of CI's
//! time is compiling). Run one file with
//! `cargo test -p tyreroad-multipoint --test integration <file>::`.

mod clusters;
mod distributed;
mod krylov;
mod recovery;
mod solver;
