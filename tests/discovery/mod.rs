//! Discovery layer: mapping helpers (fusion, registration) and Algorithm 1 against a small
//! kinematic test world built from ground-truth scene models.

mod algorithm;
mod confident;
mod mapping;
mod scenes;
mod world;
