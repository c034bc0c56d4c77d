//! Helpers shared by the integration tests.
// Each test binary uses its own part of this module.
#![allow(dead_code)]

pub mod players;
