//! Simulation backend: G-code interpreter, motion model, checks, time estimate, report.
