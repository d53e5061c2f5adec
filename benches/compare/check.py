"""Do both programs report the same rays by kind?

Each program counts with its own statistics; the rules below say how those counts must agree
for the twins to be doing the same work.

- camera: exact. Penumbra's camera and lens rays against POV-Ray's primary rays ("Rays" less
  the reflected, refracted and transmitted ones). With anti-aliasing, POV-Ray's method 1
  first traces one ray per pixel (and per pixel of the block borders it renders twice) before
  its n×n supersamples; its "Pixels" count is those, so they are taken off first.
- reflection and refraction: within TOLERANCE of Penumbra's counts scaled by POV-Ray's camera
  rays per Penumbra camera ray (the extra AA rays spawn secondaries too).
- shadow: POV-Ray counts a shadow ray again each time it passes a transparent surface (it
  restarts from the crossing), Penumbra counts it once. With opaque materials only, POV-Ray's
  "Shadow Ray Tests" must equal Penumbra's shadow plus area-shadow rays (scaled as above)
  within TOLERANCE; with transparent ones, up to POV-Ray's successful tests more (each restart
  follows a successful test), so the check is one-sided there.
"""

from dataclasses import dataclass

TOLERANCE = 0.05
# Counts this small are compared with this absolute slack instead (a handful of grazing rays).
SLACK = 50


@dataclass
class KindCheck:
    """One kind of ray: Penumbra's count, POV-Ray's, the range POV-Ray's must lie in."""

    kind: str
    penumbra: int
    povray: int
    low: float
    high: float
    note: str = ""

    @property
    def ok(self):
        return self.low <= self.povray <= self.high

    def describe(self):
        if self.low == self.high:
            want = "%d" % self.low
        else:
            want = "%.0f..%.0f" % (self.low, self.high)
        note = ", " + self.note if self.note else ""
        return "%s: Penumbra %d, POV-Ray %d (want %s%s)" % (self.kind, self.penumbra, self.povray, want, note)


def widen(low, high, tolerance=TOLERANCE):
    return min(low * (1 - tolerance), low - SLACK), max(high * (1 + tolerance), high + SLACK)


def check_rays(penumbra, povray, antialiased, transmissive):
    """KindChecks for one scene, from a Penumbra Run and a POV-Ray Run."""
    pen, pov = penumbra.rays, povray.rays
    stats = povray.extra["stats"]
    pen_primary = pen.get("camera", 0) + pen.get("lens", 0)
    initial = stats["pixels"] if antialiased else 0
    pov_primary = pov.get("camera", 0)
    note = "POV-Ray's %d first rays per pixel taken off" % initial if initial else ""
    checks = [KindCheck("camera", pen_primary, pov_primary - initial, pen_primary, pen_primary, note)]
    per_camera_ray = pov_primary / pen_primary if pen_primary else 1.0

    for kind in ("reflection", "refraction"):
        expected = pen.get(kind, 0) * per_camera_ray
        low, high = widen(expected, expected)
        checks.append(KindCheck(kind, pen.get(kind, 0), pov.get(kind, 0), max(low, 0), high))

    # POV-Ray's tests are its first segments plus its restarts, and it restarts only after a
    # successful test through a transparent surface: with its first segments within TOLERANCE
    # of Penumbra's (scaled) rays, its tests lie between that and that plus its successes.
    pen_shadow = pen.get("shadow", 0) + pen.get("area_shadow", 0)
    low, high = widen(pen_shadow * per_camera_ray, pen_shadow * per_camera_ray)
    restarts = stats["shadow_succeeded"] if transmissive else 0
    checks.append(KindCheck("shadow", pen_shadow, stats["shadow_tests"], max(low, 0), high + restarts))
    return checks
