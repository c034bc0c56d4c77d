//! The command line's test helpers: those every crate's tests share (`gmotion-testkit`,
//! its players with the `players` feature), and the player tests' pictures, which run
//! this crate's binary.

pub use gmotion_testkit::*;

pub mod pictures;
