"""POV-Ray twins of Penumbra's RON scenes: the same geometry, camera, lights, materials,
recursion depth and samples, written as POV-Ray 3.7 scene language plus command-line options.

What maps to what (docs/compare.md lists what cannot be matched):
- camera: Penumbra's vertical `fov_deg` becomes POV-Ray's horizontal `angle`; `right -x*W/H`
  makes POV-Ray's left-handed camera produce Penumbra's right-handed image. A thin lens of
  radius r becomes `aperture 4r` (POV-Ray's lens offsets reach aperture/4) focused on the point
  of the view axis at Penumbra's focus depth, with `blur_samples N, N` so no pixel stops early.
- anti-aliasing: n×n samples per pixel become `+A0.0 +AM1 +Rn` (with `+J` when jittered).
- area lights: a share of `samples / spp` shadow rays per shading point becomes an n×m
  `area_light` without `adaptive` (POV-Ray's `adaptive 0` would still sample adaptively).
- materials: `kd` is the pigment, `ambient 1` against `ambient_light` = the scene's ambient,
  `diffuse 1`, `phong ks phong_size shininess`, `reflection kr`, transmit `kt` with
  `interior { ior }`; `max_depth` becomes `max_trace_level` (both stop the same paths: the
  two programs report identical reflected and refracted ray counts) and `min_contribution`
  becomes `adc_bailout`.
"""

import math
import os
from dataclasses import dataclass, field

import mesh as meshes


class TwinError(ValueError):
    """A scene feature the twin cannot express."""


@dataclass
class Twin:
    """A POV-Ray scene and the options that go with it."""

    sdl: str
    options: list
    camera_samples: int  # camera samples per pixel Penumbra takes
    notes: list = field(default_factory=list)


def vec(v):
    return "<%.9g, %.9g, %.9g>" % tuple(v)


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def scale(v, s):
    return tuple(x * s for x in v)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def norm(v):
    return scale(v, 1.0 / math.sqrt(dot(v, v)))


def write_twin(scene, scene_dir, inc_dir):
    """The twin of the parsed RON `scene` (ron.Struct); meshes named relative to `scene_dir`
    are converted once into `mesh2` include files in `inc_dir`."""
    settings = scene.get("settings")
    get = settings.get if settings is not None else (lambda key, default=None: default)
    if get("adaptive") not in (None, "None"):
        raise TwinError("adaptive supersampling has no POV-Ray twin")
    camera = scene["camera"]
    aa = get("aa")
    aa_samples = aa.get("samples", 1) if aa is not None else 1
    aa_pattern = aa.get("pattern", "Jittered") if aa is not None else "Jittered"
    aperture = camera.get("aperture", 0.0)
    lens = camera.get("lens")
    lens_samples = (lens.get("samples", 1) if lens is not None else 1) if aperture > 0 else 1
    spp = aa_samples * lens_samples
    twin = Twin(sdl="", options=[], camera_samples=spp)

    out = ["#version 3.7;"]
    max_depth = get("max_depth", 5)
    ambient = get("ambient", (0.1, 0.1, 0.1))
    out.append(
        "global_settings { assumed_gamma 1.0 max_trace_level %d adc_bailout %.9g ambient_light rgb %s }"
        % (max_depth, get("min_contribution", 1e-3), vec(ambient))
    )
    out.append("background { rgb %s }" % vec(get("background", (0.0, 0.0, 0.0))))
    out.append(camera_block(camera, aperture, spp if aperture > 0 else 0, twin))
    if aperture > 0 and aa_samples > 1:
        twin.notes.append("lens and aa together: POV-Ray's focal blur takes all %d samples" % spp)
    elif aa_samples > 1:
        n = math.isqrt(aa_samples)
        if n * n != aa_samples:
            raise TwinError(f"aa samples {aa_samples} is not a square: POV-Ray takes n×n")
        jitter = "+J1.0" if aa_pattern != "Grid" else "-J"
        twin.options += ["+A0.0", "+AM1", f"+R{n}", jitter]

    for light in scene.get("lights", []):
        out.append(light_block(light, spp, twin))
    materials = {}
    for i, m in enumerate(scene["materials"]):
        materials[m["name"]] = (f"M{i}", m.get("kt", 0.0) > 0)
        out.append(material_block(f"M{i}", m, twin))
    declared = {}
    for obj in scene["objects"]:
        out.append(object_block(obj, materials, scene_dir, inc_dir, declared, out))
    twin.sdl = "\n".join(out) + "\n"
    return twin


def camera_block(camera, aperture, blur_samples, twin):
    width, height = camera["width"], camera["height"]
    position, look_at = camera["position"], camera["look_at"]
    up = camera.get("up", (0.0, 1.0, 0.0))
    vfov = math.radians(camera["fov_deg"])
    hfov = math.degrees(2.0 * math.atan(math.tan(vfov / 2.0) * width / height))
    twin.options += [f"+W{width}", f"+H{height}"]
    lines = [
        "camera { perspective",
        "  location %s" % vec(position),
        "  right -x*%.9g up y sky %s" % (width / height, vec(up)),
        "  angle %.9g" % hfov,
    ]
    if aperture > 0:
        forward = norm(sub(look_at, position))
        if camera.get("focus_distance") is not None:
            depth = camera["focus_distance"]
        elif camera.get("focus_on") is not None:
            depth = dot(sub(camera["focus_on"], position), forward)
        else:
            depth = math.sqrt(dot(sub(look_at, position), sub(look_at, position)))
        lines += [
            "  aperture %.9g" % (4.0 * aperture),
            "  blur_samples %d, %d" % (blur_samples, blur_samples),
            "  variance 0",
            "  focal_point %s" % vec(add(position, scale(forward, depth))),
        ]
    lines += ["  look_at %s" % vec(look_at), "}"]
    return "\n".join(lines)


def light_block(light, spp, twin):
    colour = scale(light.get("colour", (1.0, 1.0, 1.0)), light.get("intensity", 1.0))
    if light.name == "Point":
        return "light_source { %s color rgb %s }" % (vec(light["position"]), vec(colour))
    if light.name == "Directional":
        d = norm(light["direction"])
        return "light_source { %s color rgb %s parallel point_at <0, 0, 0> }" % (
            vec(scale(d, -1e5)),
            vec(colour),
        )
    per_point = -(-light.get("samples", 16) // spp)
    n = math.isqrt(per_point)
    n1, n2 = (n, n) if n * n == per_point else (per_point, 1)
    if n1 * n2 != per_point:
        twin.notes.append(f"area light of {per_point} samples per point taken as {n1}x{n2}")
    jitter = "" if light.get("pattern", "Jittered") == "Grid" else " jitter"
    if light.name == "Rect":
        eu, ev = light["edge_u"], light["edge_v"]
        centre = add(light["corner"], scale(add(eu, ev), 0.5))
        return "light_source { %s color rgb %s area_light %s, %s, %d, %d%s }" % (
            vec(centre),
            vec(colour),
            vec(eu),
            vec(ev),
            n1,
            n2,
            jitter,
        )
    if light.name == "Disk":
        normal = norm(light["normal"])
        helper = (1.0, 0.0, 0.0) if abs(normal[0]) < 0.9 else (0.0, 1.0, 0.0)
        u = norm(cross(normal, helper))
        v = cross(normal, u)
        r = 2.0 * light["radius"]
        return "light_source { %s color rgb %s area_light %s, %s, %d, %d%s circular orient }" % (
            vec(light["centre"]),
            vec(colour),
            vec(scale(u, r)),
            vec(scale(v, r)),
            n1,
            n2,
            jitter,
        )
    raise TwinError(f"light {light.name} has no POV-Ray twin")


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def material_block(name, m, twin):
    if m.get("glossiness", 0.0) > 0:
        raise TwinError(f"material {m['name']}: glossy or blurry rays have no POV-Ray twin")
    kt = m.get("kt", 0.0)
    finish = ["ambient 1", "diffuse 1"]
    if m.get("ks", 0.0) > 0:
        finish.append("phong %.9g phong_size %.9g" % (m["ks"], m.get("shininess", 32.0)))
    if m.get("kr", 0.0) > 0:
        finish.append("reflection { %.9g }" % m["kr"])
    kd = m["kd"]
    texture = "#declare %s = texture { pigment { rgbt <%.9g, %.9g, %.9g, %.9g> } finish { %s } }" % (
        name,
        kd[0],
        kd[1],
        kd[2],
        kt,
        " ".join(finish),
    )
    if kt > 0:
        texture += "\n#declare %s_interior = interior { ior %.9g }" % (name, m.get("ior", 1.5))
    return texture


def transform_block(transform):
    if transform is None:
        return ""
    parts = []
    s = transform.get("scale", (1.0, 1.0, 1.0))
    r = transform.get("rotate_deg", (0.0, 0.0, 0.0))
    t = transform.get("translate", (0.0, 0.0, 0.0))
    if tuple(s) != (1.0, 1.0, 1.0):
        parts.append("scale %s" % vec(s))
    if any(r):
        parts.append("rotate %s" % vec(r))
    if any(t):
        parts.append("translate %s" % vec(t))
    return " ".join(parts)


def object_block(obj, materials, scene_dir, inc_dir, declared, out):
    material, transmits = materials[obj["material"]]
    look = "texture { %s }" % material + (" interior { %s_interior }" % material if transmits else "")
    place = transform_block(obj.get("transform"))
    shape = obj["shape"]
    kind = shape.name
    if kind == "Sphere":
        body = "sphere { %s, %.9g" % (vec(shape["centre"]), shape["radius"])
    elif kind == "Plane":
        n = norm(shape["normal"])
        body = "plane { %s, %.9g" % (vec(n), dot(n, shape["point"]))
    elif kind == "Box":
        body = "box { %s, %s" % (vec(shape["min"]), vec(shape["max"]))
    elif kind == "Triangle":
        body = "triangle { %s" % ", ".join(vec(v) for v in shape["vertices"])
    elif kind == "Polygon":
        points = list(shape["vertices"]) + [shape["vertices"][0]]
        body = "polygon { %d, %s" % (len(points), ", ".join(vec(v) for v in points))
    elif kind == "Mesh":
        path = os.path.normpath(os.path.join(scene_dir, shape["file"]))
        smooth = shape.get("smooth", True) not in (False, "false")
        key = (path, smooth)
        if key not in declared:
            declared[key] = include_name(path, smooth)
            out.append('#include "%s"' % mesh2_include(path, smooth, inc_dir))
        body = "object { %s" % declared[key]
    else:
        raise TwinError(f"shape {kind} has no POV-Ray twin")
    return " ".join(p for p in (body, look, place, "}") if p)


def include_name(path, smooth):
    stem = os.path.splitext(os.path.basename(path))[0]
    return "MESH_" + "".join(c if c.isalnum() else "_" for c in stem) + ("_smooth" if smooth else "_flat")


def mesh2_include(path, smooth, inc_dir):
    """Writes (once) `inc_dir/NAME.inc` declaring the OBJ at `path` as a `mesh2` in object
    space, with Penumbra's smooth vertex normals when `smooth`; returns the include's path."""
    name = include_name(path, smooth)
    target = os.path.join(inc_dir, name + ".inc")
    if os.path.exists(target) and os.path.getmtime(target) >= os.path.getmtime(path):
        return target
    vertices, triangles = meshes.load_obj(path)
    parts = ["#declare %s = mesh2 {\n" % name, "vertex_vectors { %d,\n" % len(vertices)]
    parts.append("\n".join("<%.9g,%.9g,%.9g>" % tuple(v) for v in vertices.tolist()))
    parts.append("\n}\n")
    if smooth:
        normals = meshes.vertex_normals(vertices, triangles)
        parts.append("normal_vectors { %d,\n" % len(normals))
        parts.append("\n".join("<%.7g,%.7g,%.7g>" % tuple(n) for n in normals.tolist()))
        parts.append("\n}\n")
    parts.append("face_indices { %d,\n" % len(triangles))
    parts.append("\n".join("<%d,%d,%d>" % tuple(t) for t in triangles.tolist()))
    parts.append("\n}\n}\n")
    os.makedirs(inc_dir, exist_ok=True)
    temporary = target + ".tmp"
    with open(temporary, "w", encoding="utf-8") as f:
        f.write("".join(parts))
    os.replace(temporary, target)
    return target
