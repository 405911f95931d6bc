//! Machine profiles (machines/*.toml) and G-code dialects.
//!
//! A [`Profile`] is data, not code: the shipped ones are embedded in the binary
//! ([`builtin_profiles`]) and a user's own loads with [`Profile::from_toml`].
//!
//! Ranges (every violation is an error naming the file and the dotted key; there are no
//! silent clamps): work-area bounds within ±1e7 mm; `max_feed` and `acceleration` per axis
//! in (0, 1e7] (z may be 0); tool `diameter` and beam `kerf` within 0.001..=1000 mm
//! ([`TOOL_SIZE_MM`], converted to the profile's units); V-bit `angle` in (0, 180)
//! and `tip_diameter` in \[0, diameter); `power` 0 ≤ min ≤ max, max > 0; dwells
//! 0..=600 s; `gcode.decimals` 0..=6; `gcode.path_tolerance` 0..=1e7 mm; `router.safe_z` in
//! (0, work_area.z max], `clearance_z` in [0, safe_z], `plunge_feed` in (0, max_feed.z];
//! `svg.stroke_width` in (0, 10] mm. A router profile needs at least one tool. The
//! `preamble` and `postamble` must not hold `M2`/`M30` (they would end the program before
//! or instead of its `program_end`) nor `M3`/`M4` (they would start the spindle or laser
//! outside the program's own, checked, on/off sequence).

pub(crate) mod dialect;
mod number;
pub(crate) mod profile;
pub(crate) mod template;

pub use dialect::Dialect;
#[cfg(test)]
use number::rounded_scaled;
pub use number::{format_number, format_number_std};
pub(crate) use number::{pow10, push_number};
pub use profile::{
    ArcFormat, Axes, GcodeSettings, LaserMode, LaserSettings, MachineKind, OperationColors,
    PowerRange, Profile, ProfileError, ProfileErrorKind, Range, RapidOff, RouterSettings,
    SvgSettings, TOOL_SIZE_MM, Tool, ToolKind, Units, WorkArea,
};

/// The shipped profiles' file names and texts (embedded, so the binary works from anywhere).
pub const BUILTIN_SOURCES: [(&str, &str); 7] = [
    (
        "grbl-laser.toml",
        include_str!("../../machines/grbl-laser.toml"),
    ),
    (
        "grbl-router.toml",
        include_str!("../../machines/grbl-router.toml"),
    ),
    (
        "marlin-laser.toml",
        include_str!("../../machines/marlin-laser.toml"),
    ),
    (
        "linuxcnc-router.toml",
        include_str!("../../machines/linuxcnc-router.toml"),
    ),
    (
        "smoothie-laser.toml",
        include_str!("../../machines/smoothie-laser.toml"),
    ),
    (
        "svg-laser.toml",
        include_str!("../../machines/svg-laser.toml"),
    ),
    (
        "svg-laser-lightburn.toml",
        include_str!("../../machines/svg-laser-lightburn.toml"),
    ),
];

/// The shipped profiles, parsed and validated.
pub fn builtin_profiles() -> Result<Vec<Profile>, ProfileError> {
    BUILTIN_SOURCES
        .iter()
        .map(|(file, text)| Profile::from_toml(text, file))
        .collect()
}

/// The shipped profile called `name` (its `name` key, which is also its file stem); a name
/// no shipped profile has is a [`ProfileErrorKind::UnknownBuiltin`] error naming it.
pub fn builtin_profile(name: &str) -> Result<Profile, ProfileError> {
    match BUILTIN_SOURCES
        .iter()
        .find(|(file, _)| file.strip_suffix(".toml") == Some(name))
    {
        Some((file, text)) => Profile::from_toml(text, file),
        None => Err(ProfileError::unknown_builtin(name)),
    }
}

/// The names of the shipped profiles, in [`BUILTIN_SOURCES`] order.
pub fn builtin_names() -> impl Iterator<Item = &'static str> {
    BUILTIN_SOURCES
        .iter()
        .map(|(file, _)| file.strip_suffix(".toml").unwrap_or(file))
}

#[cfg(test)]
mod tests;
