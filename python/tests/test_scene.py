"""Scenes built from NumPy: meshes, instances, materials, lights, textures, cameras, and
scene.intersect against a brute-force check on the bunny."""
import numpy as np
import pytest

import librt
from conftest import data_file, read_obj


def grid_mesh(n=8):
    """An n x n grid of quads in the plane z = 0 over [0, 1]^2: 2 n^2 triangles."""
    xs = np.linspace(0.0, 1.0, n + 1, dtype=np.float32)
    x, y = np.meshgrid(xs, xs)
    vertices = np.stack([x.ravel(), y.ravel(), np.zeros(x.size, np.float32)], axis=1)
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return vertices, np.asarray(tris, np.uint32)


def test_mesh_from_numpy_round_trips():
    vertices, indices = grid_mesh()
    scene = librt.Scene()
    mat = scene.add_material("diffuse", albedo=(0.5, 0.5, 0.5))
    obj = scene.add_mesh(vertices, indices, mat)
    # One ray down through every triangle's centroid finds that triangle at distance 2.
    centroids = vertices[indices].mean(axis=1)
    origins = centroids + np.array([0, 0, 2], np.float32)
    directions = np.tile(np.array([0, 0, -1], np.float32), (len(indices), 1))
    hits = scene.intersect(origins, directions)
    assert np.array_equal(hits["primitive_id"], np.arange(len(indices)))
    assert np.all(hits["object_id"] == obj)
    assert np.allclose(hits["t"], 2.0, atol=1e-6)
    assert np.allclose(np.abs(hits["normal"][:, 2]), 1.0)


def test_mesh_arrays_are_checked():
    vertices, indices = grid_mesh(2)
    scene = librt.Scene()
    mat = scene.add_material("diffuse")
    with pytest.raises(librt.Error, match="indices"):
        scene.add_mesh(vertices, indices.astype(np.float32), mat)
    with pytest.raises(librt.Error, match=r"vertices: expected an array of shape \(N, 3\)"):
        scene.add_mesh(vertices[:, :2], indices, mat)
    bad = indices.copy()
    bad[1, 2] = 99
    with pytest.raises(librt.Error):
        scene.add_mesh(vertices, bad, mat)
    with pytest.raises(librt.Error, match="normals"):
        scene.add_mesh(vertices, indices, mat, normals=np.zeros((2, 3), np.float32))


def test_instances_place_a_prototype():
    vertices, indices = grid_mesh(2)
    scene = librt.Scene()
    mat = scene.add_material("mirror")
    proto = scene.add_mesh_prototype(vertices, indices)
    transform = np.eye(4, dtype=np.float32)
    transform[:3, 3] = [10, 0, 0]  # row-major: translation in the last column
    scene.add_instance(proto, transform, mat)
    transform[:3, 3] = [20, 0, 5]
    scene.add_instance(proto, transform, mat)
    origins = np.array([[10.5, 0.5, 3], [20.5, 0.5, 8], [0.5, 0.5, 3]], np.float32)
    directions = np.tile(np.array([0, 0, -1], np.float32), (3, 1))
    hits = scene.intersect(origins, directions)
    assert list(hits["instance_id"]) == [0, 1, -1]
    assert np.allclose(hits["t"][:2], 3.0) and np.isinf(hits["t"][2])


def test_every_material_kind_and_light_renders():
    scene = librt.Scene()
    kinds = [librt.Material("diffuse", albedo=(0.8, 0.2, 0.2)),
             librt.Material("mirror", albedo=(0.9, 0.9, 0.9)),
             librt.Material("dielectric", ior=1.33),
             librt.Material("rough_dielectric", ior=1.5, roughness=0.3),
             librt.Material("conductor", metal="gold", roughness=0.1),
             librt.Material("conductor", eta=(0.2, 0.9, 1.1), k=(3.9, 2.4, 2.2), roughness=0.4),
             librt.Material("metallic_roughness", base_color=(0.2, 0.4, 0.9), metallic=0.5,
                            roughness=0.3, clearcoat=0.5, sheen_color=(0.3, 0.3, 0.3)),
             librt.Material("emissive", emission=(2, 2, 2))]
    assert [m.kind for m in kinds] == ["diffuse", "mirror", "dielectric", "rough_dielectric",
                                       "conductor", "conductor", "metallic_roughness", "emissive"]
    assert kinds[2].ior == pytest.approx(1.33) and kinds[6].clearcoat == pytest.approx(0.5)
    for i, m in enumerate(kinds):
        scene.add_sphere((i * 2.5 - 9, 1, 0), 1.0, scene.add_material(m))
    texels = np.random.default_rng(1).random((8, 8, 3), dtype=np.float32)
    tex = scene.add_texture(texels)
    floor = scene.add_material("diffuse", albedo_texture=tex)
    scene.add_mesh(np.array([[-20, 0, -20], [20, 0, -20], [20, 0, 20], [-20, 0, 20]], np.float32),
                   np.array([[0, 2, 1], [0, 3, 2]], np.uint32), floor,
                   uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32))
    scene.add_point_light((0, 5, 5), (20, 20, 20))
    scene.add_sphere_light((5, 6, 2), 0.5, (10, 10, 10))
    scene.add_quad_light((-1, 8, -1), (2, 0, 0), (0, 0, 2), (5, 5, 5))
    scene.add_disk_light((0, 7, 0), (0, -1, 0), 1.0, (4, 4, 4))
    scene.add_spot_light((0, 6, 4), (0, -1, -0.5), (30, 30, 30), 0.2, 0.5)
    scene.add_directional_light((0.3, 1, 0.2), (1.5, 1.5, 1.5), angular_radius=0.01)
    scene.add_environment_light(radiance=(0.1, 0.12, 0.15))
    assert scene.light_count >= 7
    for camera in [librt.Camera.perspective((0, 3, 14), (0, 1, 0), fov=50, size=(40, 20)),
                   librt.Camera.orthographic((0, 3, 14), (0, 1, 0), xmag=11, ymag=5.5, size=(40, 20)),
                   librt.Camera.thin_lens((0, 3, 14), (0, 1, 0), lens_radius=0.2,
                                          focal_distance=14, size=(40, 20))]:
        img = librt.render(scene, camera, spp=2)
        assert img.shape == (20, 40, 3) and np.isfinite(img).all() and img.mean() > 0


def test_unknown_keywords_are_refused():
    with pytest.raises(TypeError, match="albeda"):
        librt.Material("diffuse", albeda=(1, 0, 0))
    with pytest.raises(librt.Error, match="plastic"):
        librt.Material("plastic")
    with pytest.raises(TypeError, match="zoom"):
        librt.Camera(zoom=2)


def test_camera_look_at():
    camera = librt.Camera(size=(20, 10)).look_at((1, 2, 3), (0, 0, 0), up=(0, 0, 1))
    assert camera.position == pytest.approx((1, 2, 3)) and camera.up == pytest.approx((0, 0, 1))
    assert camera.size == (20, 10) and camera.projection == "perspective"
    camera.projection = "orthographic"
    camera.lens = "pinhole"
    camera.validate()
    with pytest.raises(librt.Error):
        camera.projection = "fisheye"


def brute_force_closest(origins, directions, v0, v1, v2):
    """Closest hit t and triangle of each ray, by Moller-Trumbore over every triangle (float64)."""
    e1, e2 = v1 - v0, v2 - v0
    ts = np.full(len(origins), np.inf)
    ids = np.full(len(origins), -1)
    for r, (o, d) in enumerate(zip(origins, directions)):
        p = np.cross(d, e2)
        det = np.einsum("ij,ij->i", e1, p)
        ok = np.abs(det) > 1e-14
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = o - v0
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ d) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        if hit.any():
            k = np.argmin(np.where(hit, t, np.inf))
            ts[r], ids[r] = t[k], k
    return ts, ids


def test_intersect_agrees_with_brute_force_on_the_bunny():
    vertices, indices = read_obj(data_file("stanford-bunny.obj"))
    scene = librt.Scene()
    scene.add_mesh(vertices, indices, scene.add_material("diffuse"))
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, radius = (lo + hi) / 2, float(np.linalg.norm(hi - lo)) / 2
    rng = np.random.default_rng(39)
    n = 100_000
    # Rays from a sphere around the bunny toward random points inside its box.
    dirs = rng.normal(size=(n, 3))
    origins = (centre + 2 * radius * dirs / np.linalg.norm(dirs, axis=1, keepdims=True)).astype(np.float32)
    targets = (lo + rng.random((n, 3)) * (hi - lo)).astype(np.float32)
    directions = (targets - origins).astype(np.float32)
    hits = scene.intersect(origins, directions)
    hit = np.isfinite(hits["t"])
    assert 0.2 < hit.mean() < 0.9  # a real mix of hits and misses
    # Every hit lies on the triangle it names.
    o64, d64 = origins.astype(np.float64), directions.astype(np.float64)
    tri = vertices.astype(np.float64)[indices.astype(np.int64)]
    ids = hits["primitive_id"][hit]
    p = o64[hit] + hits["t"][hit, None] * d64[hit]
    a, b, c = tri[ids, 0], tri[ids, 1], tri[ids, 2]
    n_tri = np.cross(b - a, c - a)
    dist = np.abs(np.einsum("ij,ij->i", p - a, n_tri)) / np.linalg.norm(n_tri, axis=1)
    assert dist.max() < 1e-5 * radius
    # The same hits with 1 thread and with many.
    single = scene.intersect(origins, directions, threads=1)
    assert np.array_equal(single["t"], hits["t"]) and np.array_equal(single["primitive_id"], hits["primitive_id"])
    # The closest hit: 300 of the rays against every triangle.
    sample = rng.choice(n, 300, replace=False)
    bt, bid = brute_force_closest(o64[sample], d64[sample], tri[:, 0], tri[:, 1], tri[:, 2])
    lt = hits["t"][sample].astype(np.float64)
    assert np.array_equal(np.isfinite(bt), np.isfinite(lt))
    both = np.isfinite(bt)
    assert np.allclose(lt[both], bt[both], rtol=1e-5, atol=0)
    same = hits["primitive_id"][sample][both] == bid[both]
    assert same.mean() > 0.98  # a tie on a shared edge may name the neighbour, at the same t
    # The normal: the unit winding normal of the triangle named (float32 against float64).
    unit = n_tri / np.linalg.norm(n_tri, axis=1, keepdims=True)
    assert np.abs(hits["normal"][hit] - unit).max() < 1e-5
    assert np.all(hits["normal"][~hit] == 0)


def bunny_rays(n, seed):
    vertices, indices = read_obj(data_file("stanford-bunny.obj"))
    scene = librt.Scene()
    scene.add_mesh(vertices, indices, scene.add_material("diffuse"))
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    rng = np.random.default_rng(seed)
    origins = ((lo + hi) / 2 + rng.normal(size=(n, 3)) * float(np.linalg.norm(hi - lo))).astype(np.float32)
    directions = (lo + rng.random((n, 3)) * (hi - lo) - origins).astype(np.float32)
    return scene, origins, directions


def test_intersect_writes_into_the_arrays_out_gives():
    scene, origins, directions = bunny_rays(20_000, 3)
    fresh = scene.intersect(origins, directions)
    assert 0.2 < np.isfinite(fresh["t"]).mean() < 0.9
    out = {"t": np.full(20_000, 7.0, np.float32), "normal": np.full((20_000, 3), 7.0, np.float32)}
    given = dict(out)
    result = scene.intersect(origins, directions, out=out)
    assert result is out  # the caller's dict, completed with the arrays it lacked
    assert result["t"] is given["t"] and result["normal"] is given["normal"]
    assert set(result) == set(fresh)
    for key in fresh:
        assert np.array_equal(result[key], fresh[key]), key
    # Reused on other rays: every element rewritten, the same arrays.
    arrays = {k: v for k, v in result.items()}
    again = scene.intersect(origins[::-1].copy(), directions[::-1].copy(), out=result, threads=1)
    for key in fresh:
        assert again[key] is arrays[key]
        assert np.array_equal(again[key], fresh[key][::-1]), key
    # The previous call's result is a valid out=.
    scene.intersect(origins, directions, out=fresh)


def test_intersect_refuses_bad_out_arrays():
    scene, origins, directions = bunny_rays(100, 4)
    n = len(origins)
    cases = [
        ({"t": np.zeros(n, np.float64)}, r"out\['t'\]: expected a float32 array of shape \(100,\), got float64"),
        ({"t": np.zeros(n + 1, np.float32)}, r"out\['t'\]: .*got float32 of shape \(101,\)"),
        ({"normal": np.zeros((n, 4), np.float32)}, r"out\['normal'\]: expected a float32 array of shape \(100, 3\)"),
        ({"primitive_id": np.zeros(n, np.int32)}, r"out\['primitive_id'\]: expected a int64 array"),
        ({"object_id": np.zeros((n, 2), np.int64)[:, 0]}, r"out\['object_id'\]: expected a C-contiguous"),
        ({"instance_id": [0] * n}, r"out\['instance_id'\]: expected a int64 array .* got a list"),
        ({"normals": np.zeros((n, 3), np.float32)}, r"out: 'normals' is none of t, primitive_id"),
    ]
    for out, message in cases:
        with pytest.raises(librt.Error, match=message):
            scene.intersect(origins, directions, out=out)
    read_only = np.zeros(n, np.float32)
    read_only.flags.writeable = False
    with pytest.raises(librt.Error, match=r"out\['t'\]: the array is read-only"):
        scene.intersect(origins, directions, out={"t": read_only})
    with pytest.raises(librt.Error, match="out: expected a dict"):
        scene.intersect(origins, directions, out=[np.zeros(n, np.float32)])


def test_a_scene_in_use_cannot_be_changed():
    scene = librt.Scene()
    scene.add_sphere((0, 0, 0), 1.0, scene.add_material("diffuse"))
    scene.add_point_light((0, 3, 3), (10, 10, 10))
    camera = librt.Camera.perspective((0, 0, 4), (0, 0, 0), size=(64, 64))
    refused = []

    def progress(p):
        # Called while the render reads the scene (as another Python thread could be).
        try:
            scene.add_sphere((2, 0, 0), 0.5, 0)
        except librt.Error as e:
            refused.append(str(e))
        return False

    with pytest.raises(librt.Cancelled):
        librt.render(scene, camera, spp=1 << 20, progress=progress)
    assert refused and "while a render or ray query uses it" in refused[0]
    scene.add_sphere((2, 0, 0), 0.5, 0)  # free again once the render has returned
    assert scene.object_count == 2
