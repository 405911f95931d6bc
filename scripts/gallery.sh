#!/usr/bin/env bash
# Regenerate examples/gallery/: every design, its checked machine output and its preview
# image. Run from anywhere: `bash scripts/gallery.sh` (CI runs it too).
#
# Each design is made the way a user would make it (`skinpath text`, `skinpath import`,
# `skinpath init`, or written by hand), built for its own machine with --preview, checked
# with `skinpath check`, and also built and checked on grbl-laser, grbl-router and
# svg-laser with default flags. Previews are PNGs from skinpath's own preview renderer
# (`build --preview NAME.png`, the same drawing as the SVG preview, painted by tiny-skia).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
cargo build --release --quiet
bin="${CARGO_TARGET_DIR:-$root/target}/release/skinpath"
g=examples/gallery
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

# --- the designs ---------------------------------------------------------------------

# 1. Neon sign: the word from `skinpath text`, a 6.5 mm channel for 6 mm LED neon flex
#    along the letters (one channel network where strokes meet: the union of their regions),
#    wire holes at the stroke ends, and the backboard cut around the lettering.
"$bin" text "OPEN" --height 40 --width 6 --name open -o $g/neon_open.toml
cat >> $g/neon_open.toml <<'TOML'

[[operation]]
kind = "channel"
width = 6.5
depth = 10.0
power = 80.0

[[operation]]
kind = "holes"
diameter = 4.0
depth = 12.0
power = 80.0

[[operation]]
kind = "backboard"
margin = 6.0
depth = 12.0
power = 90.0
TOML

# 2. Joining script, cut on the line by a laser.
"$bin" text "hello" --font script --height 30 --width 3 --name hello -o $g/script_hello.toml
cat >> $g/script_hello.toml <<'TOML'

[[operation]]
kind = "profile"
side = "on"
power = 70.0
depth = 2.0
TOML

# 3. A drawing imported from an SVG (its filled plate becomes a shape).
"$bin" import $g/landscape.svg -o $g/landscape.toml

# 3b. A badge imported from an SVG of filled shapes and strokes: `import` writes the
#     operations it chose (the 1 mm tag outline a line cut once, the wider stroke and the
#     fills profiled); the user adds a hatch that engraves the filled areas.
"$bin" import $g/badge.svg -o $g/badge.toml
cat >> $g/badge.toml <<'TOML'

[[operation]]
kind = "fill"
strokes = ["border", "star", "tag.fill"]
pattern = "hatch"
angle = 45.0
spacing = 0.5
power = 35.0
depth = 0.3
TOML

# 4. Laser engraving: two centred lines, hatched.
"$bin" text 'SKIN\nPATH' --height 24 --width 5 --align centre --letter-spacing 2 \
  --name words -o $g/engraving.toml
cat >> $g/engraving.toml <<'TOML'

[[operation]]
kind = "fill"
pattern = "hatch"
angle = 30.0
spacing = 0.6
power = 40.0
depth = 0.5

[[operation]]
kind = "profile"
side = "on"
power = 80.0
depth = 1.0
TOML

# 5. Router job: letters cut out, outside the outline, with holding tabs.
"$bin" text "CAFE" --height 50 --width 10 --name cafe -o $g/router_cafe.toml
cat >> $g/router_cafe.toml <<'TOML'

[[operation]]
kind = "profile"
side = "outside"
depth = 6.0
step_down = 2.0
tabs = { count = 2, width = 4.0, height = 1.5 }
power = 90.0
TOML

# 6. The starter design of `skinpath init`, as it comes.
rm -f $g/starter.toml
"$bin" init -o $g/starter.toml

# 7. Strokes with corners, by hand: a star and a lightning bolt.
cat > $g/corners.toml <<'TOML'
# Strokes with corners: each listed point is a sharp corner, where the stroke is split into
# pieces that meet in a round joint.
version = 1

[[stroke]]
name = "star"
closed = true
points = [[58.0, 100.0, 2.5], [69.8, 66.2, 2.5], [105.6, 65.5, 2.5], [77.0, 43.8, 2.5],
          [87.4, 9.5, 2.5], [58.0, 30.0, 2.5], [28.6, 9.5, 2.5], [39.0, 43.8, 2.5],
          [10.4, 65.5, 2.5], [46.2, 66.2, 2.5]]
corners = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]

[[stroke]]
name = "bolt"
points = [[140.0, 100.0, 1.5], [122.0, 60.0, 3.0], [138.0, 60.0, 3.0], [120.0, 10.0, 1.0]]
corners = [1, 2]

[[operation]]
kind = "profile"
side = "on"
power = 75.0
depth = 3.0
TOML

# 8. V-carving brush strokes: the depth follows the stroke radius (z = -r cot(θ/2)), flat
#    beyond max_depth (deeper than these strokes need).
cat > $g/vcarve_brush.toml <<'TOML'
# Brush strokes for a V-bit: each disk's radius sets the carving depth along the spine.
version = 1

[[stroke]]
name = "stem"
points = [[15.0, 10.0, 0.4], [35.0, 30.0, 2.5], [60.0, 45.0, 3.5], [90.0, 50.0, 2.0], [115.0, 45.0, 0.4]]

[[stroke]]
name = "leaf"
points = [[45.0, 40.0, 0.4], [40.0, 60.0, 3.0], [50.0, 80.0, 4.0], [70.0, 90.0, 0.4]]

[[stroke]]
name = "curl"
points = [[85.0, 58.0, 0.4], [100.0, 75.0, 2.5], [120.0, 72.0, 2.0], [118.0, 60.0, 0.5]]

[[operation]]
kind = "vcarve"
angle = 60.0
max_depth = 8.0
power = 50.0
TOML

# 9. Neon sign in script with an accent and an ampersand, as `text --neon` writes it:
#    the [neon] table for 6 mm flex, channels along the smooth script strokes, wire holes
#    where the flex runs end, one bridged backboard; the build prints the bill of materials.
"$bin" text "Café & Bar" --font script --height 22 --neon --name sign -o $g/neon_script.toml

# --- build, check, preview -------------------------------------------------------------

own_machine() {
  case "$1" in
    neon_open|neon_script|router_cafe|vcarve_brush) echo grbl-router ;;
    landscape) echo svg-laser ;;
    *) echo grbl-laser ;;
  esac
}

for design in $g/*.toml; do
  name="$(basename "$design" .toml)"
  machine="$(own_machine "$name")"
  for m in grbl-laser grbl-router svg-laser; do
    ext=gcode
    [ "$m" = svg-laser ] && ext=svg
    args=()
    [ "$m" = "$machine" ] && args=(--preview "$g/$name.png")
    "$bin" build "$design" --machine "$m" -o "$out/$name-$m.$ext" "${args[@]}" > /dev/null
    if [ "$ext" = gcode ]; then
      "$bin" check "$out/$name-$m.$ext" --machine "$m" > "$out/check.txt" ||
        { cat "$out/check.txt" >&2; echo "gallery: $name on $m fails the check" >&2; exit 1; }
    fi
  done
  echo "gallery: $name ($machine) built and checked on grbl-laser, grbl-router, svg-laser"
done
