//! Interpolation and least-squares fitting of B-splines (filled by the fitting work).
