#!/usr/bin/env python3
"""Writes the scene files of bench_scenes (benchmarks/scenes/*.yaml) from the numbers below.

The loader's lattice keeps every particle's bounding sphere clear of its neighbours' (spacing at
least the bounding diameter), so the densest start a scene file can write is a face-centred cubic
(FCC) arrangement of touching bounding spheres: four lattices, each of cube side a = sqrt(2) d,
offset by half a side on two axes, which puts every particle at d from its twelve nearest
neighbours (a packing fraction of 0.74 for the spheres, 0.49 for 10 mm dodecahedra in random
orientations). Where the container is round, each layer of the FCC stack is its own pair of
lattice entries, cut to the width of the container at that height; a layer's points lie in the
plane z = layer height (one point across the entry's box in z).

Run it from anywhere: `/usr/bin/python3 benchmarks/scenes/generate.py`. The scenes' header
comments are written here too, so edit them here.
"""

import math
import os
import textwrap

HERE = os.path.dirname(os.path.abspath(__file__))

D = 0.010  # circumscribed (bounding) diameter of the dodecahedra, m
R = D / 2
A = 0.0141422  # FCC cube side, sqrt(2) D rounded up: nearest neighbours at D (+0.04 um)
H = A / 2  # height between FCC layers
CLEAR = 0.0001  # bounding sphere to wall, m
EPS = 1e-6  # added to each box's upper bounds, so that round-off loses no lattice point

RESIN = """materials:
  # Paper section 3.2 (Table 2), as in validation/dodecahedron_packing.
  resin: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: %s,
          restitution: 0.1}

templates:
  grain: {shape: dodecahedron:0.01, material: resin}
"""

EFFECTS = """effects:
  gravity: [0, 0, -9.81]
  contact: volume
  friction: true
  rotation: true
"""


def num(x):
    """A coordinate as written: at most 7 decimals, no trailing zeros."""
    text = f"{x:.7f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def lattice(lo, hi, spacing, comment=""):
    """One lattice entry: points at lo + spacing (i + 1/2) inside [lo, hi]."""
    region = (f"{{box: {{min: [{', '.join(num(v) for v in lo)}], "
              f"max: [{', '.join(num(v + EPS) for v in hi)}]}}}}")
    tail = f"  # {comment}" if comment else ""
    return (f"  - lattice: {{template: grain, random_orientation: true, "
            f"spacing: [{', '.join(num(s) for s in spacing)}],\n"
            f"             region: {region}}}{tail}\n")


def count_points(first, last, step):
    return int(round((last - first) / step)) + 1


def layer_entries(z, xs, ys, shift, spacing_z=0.02):
    """The two lattices of one FCC layer at height z: points x0 + A i, y0 + A j (the first) and
    x0 + A/2 + A i, y0 + A/2 + A j (the second), shifted by (A/2, 0) on odd layers; `xs`, `ys`
    bound the points' centres. Returns (text, count)."""
    text, count = "", 0
    for dx, dy in ((shift, 0.0), (shift + A / 2, A / 2)):
        dx = dx % A
        x0 = xs[0] + ((dx - xs[0]) % A)  # the first point x0 = dx (mod A) at or above xs[0]
        y0 = ys[0] + ((dy - ys[0]) % A)
        if x0 > xs[1] or y0 > ys[1]:
            continue
        nx = int(math.floor((xs[1] - x0) / A + 1e-9)) + 1
        ny = int(math.floor((ys[1] - y0) / A + 1e-9)) + 1
        x1, y1 = x0 + (nx - 1) * A, y0 + (ny - 1) * A
        lo = (x0 - A / 2, y0 - A / 2, z - spacing_z / 2)
        hi = (x1 + A / 2, y1 + A / 2, z + spacing_z / 2)
        text += lattice(lo, hi, (A, A, spacing_z), f"{nx} x {ny}")
        count += nx * ny
    return text, count


def wrap_header(text):
    """The leading comment re-wrapped to 98 columns, a paragraph at each line that begins with
    Start:, Outputs or Generated."""
    lines = text.split("\n")
    n = 0
    while n < len(lines) and lines[n].startswith("#"):
        n += 1
    paragraphs = []
    for line in lines[:n]:
        words = line[1:].strip()
        if not paragraphs or words.startswith(("Start:", "Outputs", "Generated")):
            paragraphs.append(words)
        else:
            paragraphs[-1] += " " + words
    header = []
    for paragraph in paragraphs:
        header += textwrap.wrap(paragraph, 98, initial_indent="# ", subsequent_indent="# ")
    return "\n".join(header + lines[n:])


def write(name, text):
    with open(os.path.join(HERE, name), "w", encoding="utf-8") as f:
        f.write(wrap_header(text))


def fcc_box(lo_centre, cells):
    """Four lattices filling cells[0] x cells[1] x cells[2] FCC cubes whose first point (the
    lowest corner's) is at lo_centre: returns (text, count, highest centre)."""
    text, count = "", 0
    offsets = ((0, 0, 0), (A / 2, A / 2, 0), (A / 2, 0, A / 2), (0, A / 2, A / 2))
    top = 0.0
    for off in offsets:
        first = [lo_centre[k] + off[k] for k in range(3)]
        last = [first[k] + (cells[k] - 1) * A for k in range(3)]
        lo = [first[k] - A / 2 for k in range(3)]
        hi = [last[k] + A / 2 for k in range(3)]
        n = cells[0] * cells[1] * cells[2]
        text += lattice(lo, hi, (A, A, A), f"{cells[0]} x {cells[1]} x {cells[2]}")
        count += n
        top = max(top, last[2])
    return text, count, top


def bed(name, cells, header, step, end, outputs):
    """A dense bed on the floor of an open box: FCC of touching bounding spheres, the lowest
    layer's spheres on the floor and the outer ones on the side walls."""
    c = R + CLEAR
    text, count, top = fcc_box((c, c, c), cells)
    side = [c + (cells[k] - 1) * A + A / 2 + c for k in range(2)]
    height = round(2 * (top + c), 2)
    scene = header.format(count=count, top=top + R) + f"""time: {{step: {step}, end: {end}}}
seed: 18

{RESIN % "0.8"}
particles:
{text}
walls:
  - box: {{name: box, min: [0, 0, 0], max: [{num(side[0])}, {num(side[1])}, {num(height)}],
          open_top: true, material: resin}}

{EFFECTS}
{outputs}"""
    write(name, scene)
    return count


def drum_layers(radius, segments, half_length, want):
    """FCC layers from the bottom of a drum of axis y up, each as wide as the circle (the
    polygon's flat sides) allows at its height, while the count stays at most `want`.
    Returns (text, count, highest centre)."""
    inner = radius * math.cos(math.pi / segments) - R - CLEAR  # centres within this
    ys = (-(half_length - R - CLEAR), half_length - R - CLEAR)
    text, count, layer = "", 0, 0
    z = -inner
    while True:
        half = math.sqrt(max(inner * inner - z * z, 0.0))
        layer_text, n = layer_entries(z, (-half, half), ys, (layer % 2) * A / 2)
        if count + n > want:
            return text, count, z - H
        text += f"  # layer {layer}, z = {num(z)}\n" + layer_text
        count += n
        layer += 1
        z += H


def quasi2d_drum():
    """Paper section 3.4: a drum 0.3 m across and 11 mm deep; one layer of particles, packed
    hexagonally in the x-z plane (rows 10 mm apart, alternate rows shifted by half), from the
    bottom up to 300 particles."""
    radius, segments, depth, want = 0.15, 256, 0.011, 300
    inner = radius * math.cos(math.pi / segments) - R - CLEAR
    dz = D * math.sqrt(3) / 2
    text, count, row = "", 0, 0
    while count < want:
        z = -inner + row * dz
        half = math.sqrt(max(inner * inner - z * z, 0.0))
        shift = (row % 2) * D / 2
        xs = [shift + k * D for k in range(-40, 41) if abs(shift + k * D) <= half + 1e-12]
        if count + len(xs) > want:
            xs = sorted(sorted(xs, key=abs)[:want - count])
        lo = (xs[0] - D / 2, -depth / 2, z - 0.01)
        hi = (xs[-1] + D / 2, depth / 2, z + 0.01)
        text += lattice(lo, hi, (D, depth, 0.02), f"row {row}: {len(xs)}")
        count += len(xs)
        row += 1
    scene = f"""# Paper section 3.4, the quasi-2D rotating drum: {count} regular dodecahedra of 10 mm
# (circumscribed diameter) in a drum 0.3 m across and 11 mm deep (Table 3), turning at 45 rpm,
# the paper's time step 1e-5 s and section 3.2's materials with friction 0.7. The paper gives no
# particle count; issue 18 takes 300, a bed about a third of the drum deep. The drum is a
# 256-sided polygon (1,024 facets with its two caps).
# Start: one layer packed hexagonally in the x-z plane (bounding spheres touching, the closest a
# lattice may place them), filling the drum from its bottom up; the bed falls into contact
# from 0.02 s, its contacts level off after 0.08 s and its kinetic energy after 0.15 s (talus
# run's probes; bench_scenes settles it first).
# Outputs as the paper's comparison would write them: trajectories every 5e-4 s (the camera's
# sampling interval, Table 3; 50 steps), probes every 200 steps.
# Generated by generate.py (edit there).
time: {{step: 1.0e-5, end: 2.0}}
seed: 34

{RESIN % "0.7"}
particles:
{text}
walls:
  - drum: {{name: drum, center: [0, 0, 0], axis: [0, 1, 0], radius: {radius}, length: {depth},
           segments: {segments}, material: resin,
           motion: {{rotation: {{axis: [0, 1, 0], point: [0, 0, 0], rpm: 45}}}}}}

{EFFECTS}
outputs:
  trajectories: {{every: 50, directory: frames}}
  probes: {{every: 200, file: probes.csv,
           quantities: [kinetic_energy, contact_count, wall_forces, energy]}}
"""
    write("drum_quasi2d.yaml", scene)
    return count


def drum_1e6():
    radius, segments, length, want = 0.6, 1024, 1.65, 1000000
    text, count, top = drum_layers(radius, segments, length / 2, want)
    scene = f"""# A large rotating drum: {count:,} regular dodecahedra of 10 mm in a drum 1.2 m across
# and 1.65 m long, a 1,024-sided polygon (4,096 facets with its caps), turning at 22.5 rpm:
# the Froude number w^2 R / g of section 3.4's drum (0.34), so the same cascading flow at 4
# times the radius. Section 3.2's materials with friction 0.7 as in section 3.4; time step 2e-5 s
# (0.23 of the critical step talus run prints).
# Start: the drum's lower part, to {100 * (top + R + 0.6) / 1.2:.0f} % of its diameter, filled with
# FCC layers of touching bounding spheres (the densest a lattice may place them), each layer
# as wide as the drum at its height (two lattice entries a layer, so the file loads in about a
# second). The bed falls by a third of its depth, 0.17 m, in about 0.2 s, and takes a tenth of a
# turn (0.27 s) to reach its slope; bench_scenes settles it for 0.35 s first.
# Outputs as a user of a run this size writes them: probes every 200 steps, trajectory frames
# (HDF5, by default at this size) every 10,000 steps (0.2 s).
# Generated by generate.py (edit there).
time: {{step: 2.0e-5, end: 10.0}}
seed: 35

{RESIN % "0.7"}
particles:
{text}
walls:
  - drum: {{name: drum, center: [0, 0, 0], axis: [0, 1, 0], radius: {radius}, length: {length},
           segments: {segments}, material: resin,
           motion: {{rotation: {{axis: [0, 1, 0], point: [0, 0, 0], rpm: 22.5}}}}}}

{EFFECTS}
outputs:
  trajectories: {{every: 10000, directory: frames}}
  probes: {{every: 200, file: probes.csv, quantities: [kinetic_energy, wall_forces, energy]}}
"""
    write("drum_1e6.yaml", scene)
    return count


def hopper():
    """A conical hopper, outlet open from the start, filled with FCC layers, each a square
    inscribed in the cone at its height."""
    base_radius, top_radius, height, segments = 0.045, 0.18, 0.25, 128
    slope = (top_radius - base_radius) / height
    cos_half = 1 / math.sqrt(1 + slope * slope)  # the cone's half-angle's cosine
    text, count, layer = "", 0, 0
    z = R + CLEAR
    while True:
        # A bounding sphere at distance rho from the axis is clear of the cone (whose facets'
        # centres lie at radius r cos(pi / segments)) when (r' - rho) cos >= R + CLEAR.
        r_here = (base_radius + slope * (z - R)) * math.cos(math.pi / segments)
        rho = r_here - (R + CLEAR) / cos_half
        if z + R > height:
            break
        half = rho / math.sqrt(2)
        layer_text, n = layer_entries(z, (-half, half), (-half, half), (layer % 2) * A / 2)
        if n:
            text += f"  # layer {layer}, z = {num(z)}\n" + layer_text
            count += n
        layer += 1
        z += H
    scene = f"""# Hopper discharge: {count:,} regular dodecahedra of 10 mm flowing out of a conical hopper
# 0.36 m across at the top and 0.25 m high through an open outlet 90 mm across (9 particle
# diameters: through 60 mm their flow fell to a few hundred a second within 0.1 s, arching), the
# hopper's side at 28
# degrees from the vertical; section 3.2's materials (friction 0.8), time step 2e-5 s. Particles
# that fall 0.1 m below the outlet leave the domain and are removed, as a discharge run is
# written.
# Start: FCC layers of touching bounding spheres (the densest a lattice may place them), each a
# square inscribed in the cone at its height, from the outlet up to the rim; the outlet is open
# from the start. The bed lands by 0.13 s, the particles start to leave at 0.15 s and, after the
# first gush, leave at a steady 2,500 a second or so from 0.22 s (talus run's probes; the hopper
# empties in about 3 s); bench_scenes settles it for 0.25 s first.
# Outputs: probes every 250 steps with the wall forces, trajectory frames every 0.05 s (2,500
# steps).
# Generated by generate.py (edit there).
time: {{step: 2.0e-5, end: 4.0}}
seed: 36
domain: {{min: [-0.25, -0.25, -0.1], max: [0.25, 0.25, 0.3]}}

{RESIN % "0.8"}
particles:
{text}
walls:
  - hopper: {{name: hopper, base: [0, 0, 0], axis: [0, 0, 1], bottom_radius: {base_radius},
             top_radius: {top_radius}, height: {height}, outlet: open, segments: {segments},
             material: resin}}

{EFFECTS}
outputs:
  trajectories: {{every: 2500, directory: frames}}
  probes: {{every: 250, file: probes.csv, quantities: [kinetic_energy, wall_forces, energy]}}
"""
    write("hopper.yaml", scene)
    return count


def effects_drum():
    """bench_effects' scene: every effect and every output of the scene format at once, so that
    each one's cost is the difference when it is taken away (benchmarks/effect_cases.hpp).

    The drum turns 1 / 100 of a turn (one side of its polygon) every 1,000 steps, and the settle
    is a whole number of thousands of steps, so the drum that bench_effects holds still
    (without_moving_walls) stands where the turning one has turned to, facet on facet. The feed
    starts where the settle ends, so every variant starts from the same particles."""
    radius, segments, length, want = 0.11, 100, 0.1, 2500
    rpm, step, settle = 30, 2.0e-5, 12000
    per_side = 60 / (rpm * segments) / step  # steps per side of the polygon
    assert abs(per_side - round(per_side)) < 1e-9 and settle % round(per_side) == 0
    text, count, top = drum_layers(radius, segments, length / 2, want)
    half = length / 2
    feed_start = settle * step
    inner = half - R - CLEAR
    scene = f"""# The effect-cost scene of bench_effects: {count:,} regular dodecahedra of 10 mm in a drum
# 0.22 m across and 0.1 m long that turns at 30 rpm (Froude number w^2 R / g = 0.11, a rolling
# bed) between two static end plates, as drums with glass ends are built; section 3.2's materials
# with friction 0.7, time step 2e-5 s (0.23 of the critical step talus run prints). Every effect
# a scene can name is on: gravity, the volume law with friction, rotation, quadratic air drag
# (alpha = 4e-5 kg/m: 1/2 rho_air C_d A of a 10 mm grain), the static walls (the plates), the
# moving wall (the drum, a 100-sided polygon) and a feed that drops {int(2000 * 0.1)} more grains
# from above the bed at 2,000 a second from {feed_start:g} s, one every 25 steps.
# Start: the drum's lower half filled with FCC layers of touching bounding spheres (the densest
# a lattice may place them), each layer as wide as the drum at its height; the bed falls
# together by 0.1 s and turns with the drum; bench_effects settles it for {settle:,} steps
# ({feed_start:g} s: {round(rpm / 60 * feed_start * segments)} sides of the drum's polygon), where the feed begins.
# Outputs: all the scene format has, each due within every timed window of bench_effects
# (host: 100 steps): trajectory frames (CSV), ParaView files (surfaces) and checkpoints every 100
# steps (2 ms: 500 frames a second, a high-speed camera's rate, as drum experiments film), probes
# every 20 steps with every quantity.
# Generated by generate.py (edit there).
time: {{step: 2.0e-5, end: 1.0}}
seed: 37

{RESIN % "0.7"}
particles:
{text}  - feed: {{template: grain, rate: 2000, start: {feed_start:g}, stop: {feed_start + 0.1:g},
           velocity: [0, 0, -0.5], region: {{box: {{min: [-0.03, -{num(inner)}, 0.03],
                                                max: [0.03, {num(inner)}, 0.07]}}}}}}

walls:
  - cylinder: {{name: drum, base: [0, -{num(half)}, 0], axis: [0, 1, 0], radius: {radius},
               height: {length}, segments: {segments}, material: resin,
               motion: {{rotation: {{axis: [0, 1, 0], point: [0, 0, 0], rpm: {rpm}}}}}}}
  - plane: {{name: front, point: [0, -{num(half)}, 0], normal: [0, 1, 0], size: 0.26,
            material: resin}}
  - plane: {{name: back, point: [0, {num(half)}, 0], normal: [0, -1, 0], size: 0.26,
            material: resin}}

{EFFECTS}  drag: {{alpha: 4.0e-5}}

outputs:
  trajectories: {{every: 100, directory: frames, format: csv}}
  vtk: {{every: 100, directory: vtk, particles: surfaces}}
  checkpoint: {{every: 100, directory: checkpoints, keep: 2}}
  probes: {{every: 20, file: probes.csv,
           quantities: [kinetic_energy, wall_forces, contact_count, bed_height, energy]}}
"""
    write("effects.yaml", scene)
    return count


BED_HEADER = """# {title}: {{count:,}} regular dodecahedra of 10 mm at rest in an open box under gravity: the
# dodecahedron bed of bench_step_cpu and bench_step_gpu (which set overlapping particles in code)
# as a scene file a user writes, with section 3.2's materials (friction 0.8) and a time step of
# 2e-5 s (0.23 of the critical step).
# Start: the densest packing a lattice may place, FCC of touching bounding spheres (four
# lattices), the lowest layer's spheres on the floor, {cells} FCC cubes; the top layer's
# highest point at {{top:.3f}} m. The bed falls together by about a third of its height (to a
# packing fraction near 0.7) and is at rest {settle}; bench_scenes settles it first.
# Outputs as a user writes them: {outputs_text}.
# Generated by generate.py (edit there).
"""


def main():
    counts = {}
    counts["bed_1e4"] = bed(
        "bed_1e4.yaml", (14, 14, 13),
        BED_HEADER.format(title="A bed of 1e4", cells="14 x 14 x 13",
                          settle="after about 0.13 s (talus run's probes)",
                          outputs_text="probes every 250 steps, trajectory frames every 5,000"),
        "2.0e-5", 2.0,
        """outputs:
  trajectories: {every: 5000, directory: frames}
  probes: {every: 250, file: probes.csv,
           quantities: [kinetic_energy, contact_count, bed_height, energy]}
""")
    counts["bed_1e6"] = bed(
        "bed_1e6.yaml", (100, 100, 25),
        BED_HEADER.format(title="A bed of 1e6", cells="100 x 100 x 25",
                          settle="after about 0.2 s (the fall of its top, 0.12 m)",
                          outputs_text="probes every 200 steps, trajectory frames (HDF5 at this "
                          "size) every 10,000"),
        "2.0e-5", 2.0,
        """outputs:
  trajectories: {every: 10000, directory: frames}
  probes: {every: 200, file: probes.csv, quantities: [kinetic_energy, bed_height, energy]}
""")
    counts["drum_quasi2d"] = quasi2d_drum()
    counts["hopper"] = hopper()
    counts["drum_1e6"] = drum_1e6()
    counts["effects"] = effects_drum()
    for name, n in counts.items():
        print(f"{name}: {n} particles")


if __name__ == "__main__":
    main()
