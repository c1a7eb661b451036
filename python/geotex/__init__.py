"""geotex: 3D shape modeling with high-level descriptors (after V. Andersen, DTU 2011).

A mesh is given as two numpy arrays, V (#V×3 positions) and F (#F×3 integer triangles), or as one
object with vertices and faces (trimesh.Trimesh, open3d.geometry.TriangleMesh, anything with
`vertices` and `faces` or `triangles`), or as a result that holds one (`write_mesh("o.ply",
denoise(V, F))`; `render(r, edges=r.edge_labels)` draws its labelled edges). Every function takes keyword-only options with the names,
defaults and ranges of the command line (`geotex <command> --help`); `help(geotex.smooth)` lists
them, and `inspect.signature` shows them. Errors raise geotex.InvalidInput (a ValueError),
geotex.IoError (an OSError) or geotex.SolverError (a RuntimeError); running out of memory raises
MemoryError.

    import geotex
    V, F = geotex.generate("cube")
    Vn = geotex.add_noise(V, F, sigma=0.3)
    r = geotex.denoise(Vn, F)                       # r.V, r.F, r.edge_labels, r.parameters
    print(geotex.compare(r.V, r.F, V, F)["mean_normal_error_deg"])
"""

from __future__ import annotations

import os
from typing import Any, Callable, Iterable, List, Optional, Sequence, Tuple, Union

# OpenMP's idle threads sleep instead of spinning (unless the caller chose): on a shared machine the spinning
# took a quarter of a synthesis' CPU time (bench/synthesis.md). libgomp reads this when _geotex loads it.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

import numpy as np  # noqa: E402

from . import _geotex  # noqa: E402
from ._geotex import Error, InvalidInput, IoError, SolverError  # noqa: F401
from ._options import options_doc, table, with_options

__version__ = "0.1.0"

__all__ = [
    "Error", "InvalidInput", "IoError", "SolverError", "Result",
    "read_mesh", "write_mesh", "info", "shape_names", "generate", "add_noise", "compare", "score_edge_labels",
    "face_normals", "vertex_normals", "face_areas", "edges", "dihedral_angles", "mean_edge_length",
    "boundary_loops", "connected_components",
    "umbrella_laplacian", "cotan_matrix", "mass_matrix", "cotan_laplacian", "mean_curvature_normals",
    "smooth", "deform", "parametrize", "parametrization_quality", "phong_project", "one_form_fit", "one_form_to_vertices",
    "auto_diffusion_function",
    "MeshResult", "DenoiseResult", "AutoDenoiseResult", "MrfResult", "SurfelDenoiseResult",
    "TextureResult", "TexturedResult", "TextureExtraction", "TransferResult", "AtlasResult", "SynthesisResult",
    "ResizeResult", "FeatureMap",
    "denoise", "denoise_auto", "denoise_mrf", "denoise_mrf_normal", "denoise_surfel", "denoise_methods", "point_surfels", "pca_normals",
    "texture_extract", "texture_apply", "texture_edit", "texture_animate", "texture_transfer", "texture_atlas",
    "texture_synthesize", "read_texture", "write_texture",
    "resize", "feature_map", "render", "view",
]


class Result:
    """What a computation returned: attributes (r.V, r.F, r.edge_labels, r.parameters, …), also
    readable as r["V"]."""

    def __init__(self, **fields: Any) -> None:
        self.__dict__.update(fields)

    def __getitem__(self, key: str) -> Any:
        try:
            return self.__dict__[key]
        except KeyError:
            raise KeyError(key) from None

    def __contains__(self, key: object) -> bool:
        return key in self.__dict__

    def __getattr__(self, name: str) -> Any:  # only for names that are not fields
        raise AttributeError(f"the result has no field '{name}' (it has: {', '.join(self.__dict__)})")

    def keys(self) -> List[str]:
        return list(self.__dict__)

    def __repr__(self) -> str:
        def short(v: Any) -> str:
            if isinstance(v, np.ndarray):
                return f"array{v.shape}"
            if isinstance(v, (list, dict)) and len(v) > 6:
                return f"{type(v).__name__}[{len(v)}]"
            return repr(v)
        return "Result(" + ", ".join(f"{k}={short(v)}" for k, v in self.__dict__.items()) + ")"


MeshLike = Any


_RESULT_TABLES: dict = _geotex._result_tables()


class MeshResult(Result):
    """A result that holds a mesh, V (#V×3) and F (#F×3): accepted wherever a mesh is."""


class DenoiseResult(MeshResult):
    """A denoising result: V, F, edges (#E×2), edge_labels (#E, in edges() order), parameters (the options
    used), method and seconds, then the fields of its method (the keys of `geotex denoise --report`)."""


class TextureResult(Result):
    """A texture: V_base, F (its base mesh), height (#V), tilt (#E, in edges() order), lean (#V radians, or
    empty for the thesis' encoding) and edges."""


class TexturedResult(MeshResult):
    """A texture applied to a target: V, F (the textured target, refined where it was coarser), texture
    (the target's TextureResult), parameters (the options used)."""


# Each typed result class: its base and the C++ result tables its fields come from, the same tables the
# command's --report is written from (geotex/core/results.h; _stubgen types the stubs from this).
_RESULT_CLASSES = {
    "AutoDenoiseResult": ("DenoiseResult", ("DenoiseRun", "AutoDenoiseResult")),
    "MrfResult": ("DenoiseResult", ("DenoiseRun", "MrfResult")),
    "SurfelDenoiseResult": ("DenoiseResult", ("DenoiseRun", "SurfelDenoiseResult")),
    "TextureExtraction": ("TextureResult", ("TextureExtraction", "RunTime")),
    "TransferResult": ("TexturedResult", ("TransferResult", "RunTime")),
    "AtlasResult": ("TexturedResult", ("AtlasResult", "RunTime")),
    "SynthesisResult": ("MeshResult", ("SynthesisResult", "SynthesisQuality", "RunTime")),
    "ResizeResult": ("MeshResult", ("ResizeResult", "RunTime")),
    "FeatureMap": ("Result", ("FeatureMap",)),
}


def _result_class(name: str) -> type:
    """The result class `name`, its docstring listing the fields of its C++ result tables."""
    base_name, tables = _RESULT_CLASSES[name]
    base = globals()[base_name]
    lines = [base.__doc__ or "", "", "Fields (as `--report` has them, except those marked Python only):"]
    for f in (f for t in tables for f in _RESULT_TABLES[t]):
        unit = f" [{f['unit']}]" if f["unit"] else ""
        only = "" if f["in_report"] else " (Python only)"
        lines.append(f"    {f['name']}: {f['help']}{unit}{only}")
    return type(name, (base,), {"__doc__": "\n".join(lines) + "\n", "__module__": __name__})


AutoDenoiseResult = _result_class("AutoDenoiseResult")
MrfResult = _result_class("MrfResult")
SurfelDenoiseResult = _result_class("SurfelDenoiseResult")
TextureExtraction = _result_class("TextureExtraction")
TransferResult = _result_class("TransferResult")
AtlasResult = _result_class("AtlasResult")
SynthesisResult = _result_class("SynthesisResult")
ResizeResult = _result_class("ResizeResult")
FeatureMap = _result_class("FeatureMap")



def _is_mesh(obj: Any) -> bool:
    """Whether obj is one mesh object: a (V, F) tuple, a result that holds a mesh (V and F), or an object
    with vertices and faces/triangles (trimesh, Open3D)."""
    return ((isinstance(obj, tuple) and len(obj) == 2) or (isinstance(obj, Result) and "V" in obj and "F" in obj)
            or hasattr(obj, "vertices"))


def _arrays(mesh: MeshLike, F: Any = None) -> Tuple[Any, Any]:
    """(V, F) of a mesh given as arrays, a (V, F) tuple, a result that holds a mesh (r.V, r.F: what
    denoise(), texture_apply() … return), or an object with vertices and faces/triangles. Every function
    that takes a mesh converts it here, and only here."""
    if F is not None:
        return mesh, F
    if isinstance(mesh, tuple) and len(mesh) == 2:
        return mesh
    if isinstance(mesh, Result) and "V" in mesh and "F" in mesh:
        return mesh["V"], mesh["F"]
    if hasattr(mesh, "vertices"):
        faces = getattr(mesh, "faces", None)
        if faces is None:
            faces = getattr(mesh, "triangles", None)  # open3d.geometry.TriangleMesh
        if faces is not None:
            return np.asarray(mesh.vertices), np.asarray(faces)
    what = "a result without a mesh (no V and F)" if isinstance(mesh, Result) else type(mesh).__name__
    raise TypeError("expected a mesh: arrays V and F, a (V, F) tuple, a result with V and F, or an object with "
                    f"vertices and faces (trimesh, Open3D), not {what}")


def _path(p: Union[str, os.PathLike]) -> str:
    return os.fspath(p)


# ------------------------------------------------------------------------------------------------
# Files, shapes, noise, geometry, metrics


def read_mesh(path: Union[str, os.PathLike], strict: bool = False) -> Tuple[np.ndarray, np.ndarray]:
    """Read a mesh file (.obj, .ply, .off, .stl, .glb, .gltf; gzipped too, e.g. .ply.gz).
    Returns (V, F): V float64 #V×3, F int32 #F×3.

    Polygons are split into fans and PLY triangle strips decoded. Faces that are degenerate,
    duplicated or non-manifold are dropped with a UserWarning (strict=True raises InvalidInput
    instead). Raises IoError for missing, malformed or truncated files and InvalidInput for NaN/inf
    coordinates or out-of-range indices."""
    return _geotex.read_mesh(_path(path), strict)


def write_mesh(path: Union[str, os.PathLike], mesh: MeshLike, F: Any = None, binary: bool = True) -> None:
    """Write a mesh atomically (format from the extension: .obj, .ply, .off, .stl, .glb, .gltf;
    binary PLY/STL unless binary=False; glTF stores float32 positions).
    An existing file is replaced only once the new one is complete, and keeps its permissions."""
    V, F = _arrays(mesh, F)
    _geotex.write_mesh(_path(path), V, F, binary)


def info(mesh: MeshLike, F: Any = None) -> dict:
    """Counts, boundary loops, components, Euler characteristic, genus, mean edge length, area,
    volume, bounding box: a dict with the keys of `geotex info --json` but those about the file (both
    from one C++ table, `_geotex._result_tables()["MeshSummary"]`; genus and volume are None where
    they do not apply)."""
    return _geotex.info(*_arrays(mesh, F))


def shape_names() -> List[str]:
    """Names accepted by generate()."""
    return _geotex.shape_names()


def generate(name: str, level: int = 1, seed: int = 1, with_base: bool = False) -> Any:
    """A procedural test shape (see shape_names()). Returns (V, F), or ((V, F), (V_base, F_base))
    with with_base=True (the textured shapes' untextured base, same connectivity)."""
    return _geotex.generate(name, level, seed, with_base)


@with_options("NoiseOptions")
def add_noise(mesh: MeshLike, F: Any = None, **options: Any) -> np.ndarray:
    """Seeded noise, sigma in mean edge lengths (`geotex noise`). Returns the noisy #V×3 positions."""
    return _geotex.add_noise(*_arrays(mesh, F), options)


def compare(result: MeshLike, F: Any = None, V_truth: Any = None, F_truth: Any = None) -> dict:
    """Mean face-normal error (degrees), Ev and Hausdorff distance of a result against the truth
    (`geotex compare`): compare(V, F, V_truth, F_truth) or compare(result_mesh, None, truth_mesh).
    A dict with the keys of `geotex compare --json` but the file names."""
    if F is None:
        V, F = _arrays(result)
    else:
        V = result
    if F_truth is None:
        V_truth, F_truth = _arrays(V_truth)
    return _geotex.compare(V, F, V_truth, F_truth)


def score_edge_labels(labelled: Any, truth: Any) -> dict:
    """Precision, recall and F1 of labelled edges (#×2 vertex pairs) against the true ones, and the counts
    (labelled, truth_sharp_edges, true_positive): `geotex compare --labels --json`'s edge_labels."""
    return _geotex.score_edge_labels(labelled, truth)


def face_normals(mesh: MeshLike, F: Any = None) -> np.ndarray:
    """Unit normal per face, #F×3."""
    return _geotex.face_normals(*_arrays(mesh, F))


def vertex_normals(mesh: MeshLike, F: Any = None, weighting: str = "area") -> np.ndarray:
    """Unit normal per vertex, #V×3, from the faces weighted by 'area', 'angle' or 'uniform'."""
    return _geotex.vertex_normals(*_arrays(mesh, F), weighting)


def face_areas(mesh: MeshLike, F: Any = None) -> np.ndarray:
    """Area per face, #F."""
    return _geotex.face_areas(*_arrays(mesh, F))


def edges(mesh: MeshLike, F: Any = None) -> np.ndarray:
    """#E×2 vertex indices of the edges, in the order of every per-edge array (labels, tilt)."""
    return _geotex.edges(*_arrays(mesh, F))


def dihedral_angles(mesh: MeshLike, F: Any = None) -> np.ndarray:
    """Signed dihedral angle per edge (radians; convex > 0), in edges() order."""
    return _geotex.dihedral_angles(*_arrays(mesh, F))


def mean_edge_length(mesh: MeshLike, F: Any = None) -> float:
    """The mean edge length (the unit of noise, smoothing steps and thresholds)."""
    return _geotex.mean_edge_length(*_arrays(mesh, F))


def boundary_loops(mesh: MeshLike, F: Any = None) -> List[List[int]]:
    """The boundary loops as lists of vertex indices."""
    return _geotex.boundary_loops(*_arrays(mesh, F))


def connected_components(mesh: MeshLike, F: Any = None) -> np.ndarray:
    """Component id per vertex."""
    return _geotex.connected_components(*_arrays(mesh, F))


# ------------------------------------------------------------------------------------------------
# Toolkit (thesis ch. 5)


def umbrella_laplacian(mesh: MeshLike, F: Any = None) -> Any:
    """Umbrella operator, Eq. (5.8), as a scipy.sparse matrix."""
    return _geotex.umbrella_laplacian(*_arrays(mesh, F))


def cotan_matrix(mesh: MeshLike, F: Any = None) -> Any:
    """Symmetric cotangent matrix C (C_ij = ½(cot α + cot β)), scipy.sparse."""
    return _geotex.cotan_matrix(*_arrays(mesh, F))


def mass_matrix(mesh: MeshLike, F: Any = None, mass: str = "voronoi") -> Any:
    """Diagonal mass matrix ('voronoi', 'barycentric' or 'thesis'), scipy.sparse."""
    return _geotex.mass_matrix(*_arrays(mesh, F), mass)


def cotan_laplacian(mesh: MeshLike, F: Any = None, mass: str = "voronoi") -> Any:
    """L = M⁻¹C; Eq. (5.11) with mass='thesis'. scipy.sparse."""
    return _geotex.cotan_laplacian(*_arrays(mesh, F), mass)


def mean_curvature_normals(mesh: MeshLike, F: Any = None) -> np.ndarray:
    """H n per vertex (n/r on a sphere of radius r), Eq. (5.10)."""
    return _geotex.mean_curvature_normals(*_arrays(mesh, F))


@with_options("SmoothingOptions")
def smooth(mesh: MeshLike, F: Any = None, **options: Any) -> np.ndarray:
    """Laplacian smoothing, thesis Eq. (5.12) explicit or (5.14) implicit (`geotex smooth`).
    lambda_ is dimensionless for 'umbrella' and in squared mean edge lengths for 'cotan'.
    Returns the new #V×3 positions (same connectivity)."""
    return _geotex.smooth(*_arrays(mesh, F), options)


@with_options("EditOptions")
def deform(mesh: MeshLike, F: Any = None, handles: Optional[Sequence[int]] = None, targets: Any = None,
           **options: Any) -> ResizeResult:
    """Laplacian surface editing (Eq. 5.15–5.24, `geotex deform`): handle vertex ids and their
    #handles×3 targets. Returns #V×3 positions."""
    if handles is None or targets is None:
        raise TypeError("deform() needs handles (vertex ids) and targets (#handles×3 positions)")
    V, F = _arrays(mesh, F)
    # An array of any integer dtype: the library checks each id exactly (2**64 - 1 is named, not wrapped).
    return _geotex.deform(V, F, np.asarray(handles) if len(handles) else np.zeros(0, dtype=np.int64), targets, options)


@with_options("ParametrizationOptions")
def parametrize(mesh: MeshLike, F: Any = None, **options: Any) -> np.ndarray:
    """UV coordinates (#V×2) of a disk (Sec. 5.4, `geotex param`). InvalidInput if not a disk."""
    return _geotex.parametrize(*_arrays(mesh, F), options)


def parametrization_quality(mesh: MeshLike, F: Any = None, uv: Any = None) -> dict:
    """Flipped faces, angle and area distortion of UVs (#V×2, e.g. parametrize()'s) on a mesh:
    parametrization_quality(V, F, uv) or parametrization_quality(mesh, uv=uv). A dict with the keys of
    `geotex param --json` but the method, vertex count and time."""
    return _geotex.parametrization_quality(*_arrays(mesh, F), uv)


@with_options("PhongProjectionOptions")
def phong_project(mesh: MeshLike, F: Any = None, P: Any = None, **options: Any) -> dict:
    """Project points P (#P×3) onto a mesh along its Phong-interpolated normal field (Sec. 5.2,
    analytic cubic; `geotex project`). Returns face (−1 where none), bary, point, distance."""
    if P is None:
        raise TypeError("phong_project() needs the points P")
    return _geotex.phong_project(*_arrays(mesh, F), P, options)


@with_options("OneFormFitOptions")
def one_form_fit(mesh: MeshLike, F: Any = None, T: Any = None, **options: Any) -> np.ndarray:
    """Least-squares 1-form (Eq. 5.81–5.82) of a per-vertex tangent field T (#V×3); one coefficient per edge."""
    if T is None:
        raise TypeError("one_form_fit() needs the field T")
    return _geotex.one_form_fit(*_arrays(mesh, F), T, options)


def one_form_to_vertices(mesh: MeshLike, F: Any = None, c: Any = None) -> np.ndarray:
    """Per-vertex vectors from edge coefficients (Eq. 5.78–5.79)."""
    if c is None:
        raise TypeError("one_form_to_vertices() needs the coefficients c")
    return _geotex.one_form_to_vertices(*_arrays(mesh, F), c)


def auto_diffusion_function(mesh: MeshLike, F: Any = None, t: float = 0.1, eigenpairs: int = 100, *,
                            progress: Any = None, threads: Optional[int] = None) -> np.ndarray:
    """Auto diffusion function (Gębal et al. 2009; thesis Sec. 9.4), one value per vertex."""
    return _geotex.auto_diffusion_function(*_arrays(mesh, F), t, eigenpairs, {"progress": progress, "threads": threads})


# ------------------------------------------------------------------------------------------------
# Denoising (thesis ch. 6–7)




@with_options("AutoDenoiseOptions")
def denoise_auto(mesh: MeshLike, F: Any = None, **options: Any) -> AutoDenoiseResult:
    """The default denoiser (`geotex denoise`, --method auto): estimates the noise, reads whether the
    surface is creased or smooth, then surfels, positions fitted to them and edge labels, with every
    parameter derived from the input (auto_denoise.h). Returns a Result: V, F (same connectivity),
    edge_labels (per edges()), edges, noise_sigma, choices (what was chosen and why), creased (#F: how
    each face was read, 1 creased, 0 smooth, between: a transition), creased_share (of the area), relief (#F:
    the fine relief kept in smooth regions, 0 plain to 1), relief_share, strong (#F: the sharp fit's stronger
    smoothing taken in smooth regions), strong_share, change_kept (#F), change_kept_share, parameters."""
    return AutoDenoiseResult(**_geotex.denoise_auto(*_arrays(mesh, F), options))


@with_options("MrfOptions")
def denoise_mrf(mesh: MeshLike, F: Any = None, **options: Any) -> MrfResult:
    """MRF denoising with a vertex process and an edge-labelling process (thesis ch. 6; `geotex denoise
    --method mrf`). Returns a Result: V, F, edge_labels (per edges()), edges, energies, parameters."""
    return MrfResult(**_geotex.denoise_mrf(*_arrays(mesh, F), options))


@with_options("MrfNormalOptions")
def denoise_mrf_normal(mesh: MeshLike, F: Any = None, **options: Any) -> MrfResult:
    """Face-normal MRF with edge labelling, then vertices fitted to the normals (Sec. 6.5; `geotex
    denoise --method mrf-normal`). Returns a Result like denoise_mrf()."""
    return MrfResult(**_geotex.denoise_mrf_normal(*_arrays(mesh, F), options))


@with_options("SurfelDenoiseOptions")
def denoise_surfel(mesh: MeshLike, F: Any = None, **options: Any) -> SurfelDenoiseResult:
    """Surfel reconstruction of a piecewise-smooth surface (thesis ch. 7; `geotex denoise --method
    surfel`). Returns a Result: V, F (new connectivity with retrieval='dual'), edge_labels, normals,
    offsets, energy, parameters."""
    return SurfelDenoiseResult(**_geotex.denoise_surfel(*_arrays(mesh, F), options))


_DENOISERS = {"auto": denoise_auto, "mrf": denoise_mrf, "mrf-normal": denoise_mrf_normal, "surfel": denoise_surfel}


def denoise_methods() -> List[str]:
    """The names accepted by denoise(method=...)."""
    return list(_DENOISERS)


def denoise(mesh: MeshLike, F: Any = None, *, method: str = "auto", **options: Any) -> DenoiseResult:
    """Denoise a mesh and find its sharp edges (`geotex denoise`). `method` chooses the function
    called with the same options: 'auto' (the default) → denoise_auto(), 'mrf' → denoise_mrf(), 'mrf-normal' → denoise_mrf_normal(),
    'surfel' → denoise_surfel() (see each for its options and defaults; an option of another method
    raises TypeError). preset='thesis' gives each method as the thesis runs it."""
    fn = _DENOISERS.get(method)
    if fn is None:
        raise InvalidInput(f"unknown denoising method '{method}' ({', '.join(_DENOISERS)})")
    return fn(mesh, F, **options)


@with_options("PointSurfelOptions")
def point_surfels(P: Any, **options: Any) -> Tuple[np.ndarray, np.ndarray]:
    """Surfel reconstruction of a point cloud (kNN neighbourhoods; `geotex surfels`).
    Returns (centres, normals), each #P×3."""
    return _geotex.point_surfels(P, options)


def pca_normals(P: Any, k: int = 10) -> np.ndarray:
    """Consistently oriented PCA normals of a point cloud (#P×3)."""
    return _geotex.pca_normals(P, k)


# ------------------------------------------------------------------------------------------------
# Texture (ch. 8) and resizing (ch. 9)
#
# A texture is a Result with V_base, F (its base mesh), height (#V), tilt (#E, in edges() order),
# lean (#V radians, or empty for the thesis' encoding) and edges; texture_extract() and read_texture()
# make one, every texture_* function takes one (or any object or dict with those fields).

TextureLike = Any


def _texture(texture: TextureLike) -> Tuple[Any, Any, Any, Any, Any]:
    """(V_base, F, height, tilt, lean) of a texture given as a Result, a dict or an object."""
    def field(name: str, default: Any = KeyError) -> Any:
        if isinstance(texture, dict) or isinstance(texture, Result):
            if name in texture:
                return texture[name]
        elif hasattr(texture, name):
            return getattr(texture, name)
        if default is KeyError:
            raise TypeError(f"expected a texture (V_base, F, height, tilt and optionally lean; from texture_extract() "
                            f"or read_texture()), not {type(texture).__name__} without '{name}'")
        return default
    return field("V_base"), field("F"), field("height"), field("tilt"), field("lean", None)


def _texture_result(d: dict) -> TextureResult:
    return TextureResult(**d)


def _base_arrays(base: Any, F: Any) -> Tuple[Any, Any]:
    """A base given as a mesh (arrays, (V, F), trimesh, Open3D) or as #V×3 positions over the faces F
    (None for the latter's faces when F is None)."""
    if base is None:
        return None, None
    if _is_mesh(base):
        return _arrays(base)
    return base, F


@with_options("TextureExtractOptions")
def texture_extract(mesh: MeshLike, F: Any = None, base: Any = None, **options: Any) -> TextureExtraction:
    """Extract a height-and-tilt texture from a textured mesh (Eq. 8.4–8.7; `geotex texture extract`).

    base: the base mesh, as #V×3 positions over the textured mesh's faces (the vertex correspondence) or
    as a mesh of any connectivity (the textured vertices are projected onto it along its Phong normals);
    None (default): the automatic base (Sec. 8.3.1), set by the base options (an option of the automatic
    base given with a base raises InvalidInput).
    Returns a TextureExtraction: the texture (V_base, F, height, tilt, lean, edges), the fields of
    `geotex texture extract --report` (base_source 'given', 'projected' or 'automatic', max_error and
    height_only_error, ...: help(geotex.TextureExtraction)) and parameters."""
    V, F = _arrays(mesh, F)
    Vb, Fb = _base_arrays(base, None)
    return TextureExtraction(**_geotex.texture_extract(V, F, Vb, Fb, options))


@with_options("TextureApplyOptions")
def texture_apply(texture: TextureLike, base: Any = None, **options: Any) -> Result:
    """Apply a texture to its own base or to a deformed or rescaled one of the same connectivity
    (Sec. 8.4.2; `geotex texture apply`). base: #V×3 positions, or a mesh with the texture's faces.
    The lean's direction turns with the base's rotation from the texture's own base to this one
    (tilt_encoding 'lean'; 'lean-pushforward' turns it with the full Jacobian, 'one-form' is the
    thesis). Returns a Result: V (#V×3, the textured surface) and F."""
    Vb, F, h, t, lean = _texture(texture)
    Vn, Fn = _base_arrays(base, None)
    V = _geotex.texture_apply(Vb, F, h, t, lean, Vn, Fn, options)
    return MeshResult(V=V, F=np.asarray(F if Fn is None else Fn))


@with_options("TextureEditOptions")
def texture_edit(texture: TextureLike, **options: Any) -> TextureResult:
    """Edit a texture (Sec. 8.4.1; `geotex texture edit`): op 'set-tilt', 'wrap', 'wiggle' or
    'scale-height'. Returns the edited texture (a texture Result on the same base) with parameters."""
    return _texture_result(_geotex.texture_edit(*_texture(texture), options))


@with_options("AnimationOptions")
def texture_animate(texture: TextureLike, **options: Any) -> Result:
    """Frames of an edit in motion (Fig. 8.7; `geotex texture animate`): the tilt system is factored
    once, each frame re-solved. Returns a Result: frames (#frames×#V×3 positions), F, parameters."""
    return Result(**_geotex.texture_animate(*_texture(texture), options))


@with_options("TransferOptions")
def texture_transfer(texture: TextureLike, target: MeshLike, F_target: Any = None,
                     source_near: Optional[Sequence[float]] = None, target_near: Optional[Sequence[float]] = None,
                     **options: Any) -> TransferResult:
    """Transfer a geodesic disk of a texture onto a geodesic disk of another base (Sec. 8.3.3;
    `geotex texture transfer`). The disks are centred at source_center / target_center, or at the
    vertex nearest to the point source_near / target_near (x, y, z). A refined target raises a
    UserWarning. Returns a TransferResult: V, F (the textured target; refined where it was coarser),
    texture (the target's TextureResult), parameters, and the fields of `geotex texture transfer
    --report` (help(geotex.TransferResult)): the centres and patches, counts, and the damage (folded,
    self_intersecting faces of the textured target, the bare target's own, the excess beyond them; a
    UserWarning above damage_warning)."""
    Vt, Ft = _arrays(target, F_target)
    r = _geotex.texture_transfer(*_texture(texture), Vt, Ft, source_near, target_near, options)
    r["texture"] = _texture_result(r["texture"])
    return TransferResult(**r)


@with_options("AtlasOptions")
def texture_atlas(texture: TextureLike, target: MeshLike, F_target: Any = None,
                  source_near: Optional[Sequence[float]] = None, **options: Any) -> AtlasResult:
    """Cover a whole surface with copies of one texture disk, blended where they overlap (`geotex
    texture atlas`). The source disk is centred at source_center or at the vertex nearest to
    source_near. Returns an AtlasResult: V, F (the textured target), texture, parameters, and the
    fields of `geotex texture atlas --report` (help(geotex.AtlasResult)): centers, coverage (#V:
    largest disk weight, 0 uncovered), owner, counts, and the damage as texture_transfer() has it."""
    Vt, Ft = _arrays(target, F_target)
    r = _geotex.texture_atlas(*_texture(texture), Vt, Ft, source_near, options)
    r["texture"] = _texture_result(r["texture"])
    return AtlasResult(**r)


@with_options("SynthesisOptions")
def texture_synthesize(texture: TextureLike, target: MeshLike, F_target: Any = None, weight: Any = None,
                       direction_guide: Any = None, *, on_estimate: Optional[Callable[[dict], None]] = None,
                       **options: Any) -> SynthesisResult:
    """Grow a texture like the exemplar texture over the whole target (`geotex texture synthesize`):
    patch-based, oriented by a smooth direction field (docs/synthesis.md). weight: #V_target values in
    [0, 1], where texture grows; direction_guide: #V_target×3 guide directions (else the `direction`
    option). Returns a SynthesisResult: V (the textured target), F and V_base (the target used, refined
    where it was coarser), height, tilt, lean, parameters, and the fields of `geotex texture synthesize
    --report` (help(geotex.SynthesisResult)): field, owner, centers, scale, counts, the damage, the
    quality measures of synthesis_quality() (bench/synthesis.md) and seconds. on_estimate: a callable
    given, before the work, the estimate the CLI's first line states (a dict: vertices, seconds,
    exemplar_share, scale, refine); progress: a callable(fraction, stage) from the first second."""
    Vb, F, h, t, lean = _texture(texture)
    Vt, Ft = _arrays(target, F_target)
    if on_estimate is not None:
        options["on_estimate"] = on_estimate
    return SynthesisResult(**_geotex.texture_synthesize(Vb, F, h, t, lean, Vt, Ft, weight, direction_guide, options))


def read_texture(path: Union[str, os.PathLike]) -> TextureResult:
    """Read a texture file (PLY: base mesh, vertex height and lean, edge tilt; as the CLI writes it).
    Returns a texture Result: V_base, F, height, tilt, lean, edges."""
    return _texture_result(_geotex.read_texture(_path(path)))


def write_texture(path: Union[str, os.PathLike], texture: TextureLike, binary: bool = True) -> None:
    """Write a texture file atomically (PLY, readable by `geotex texture apply|edit|…`)."""
    _geotex.write_texture(_path(path), *_texture(texture), binary)


@with_options("ResizeRunOptions")
def resize(mesh: MeshLike, F: Any = None, deformed: Any = None, *, features: Any = "importance",
           **options: Any) -> ResizeResult:
    """Feature-aware resizing and deformation (ch. 9; `geotex resize`, the same library call).
    The deformation: scale=(sx, sy, sz), twist, bend, arc_radius (about the bounding box's centre), or
    deformed=#V×3 positions from any other deformation (e.g. deform()). features: a map name
    ('importance', the continuous default; 'auto', 'height', 'adf', binary; 'none'; the same
    feature_map() as the command line), #V weights in [0, 1] (binary or continuous, e.g. painted), or a
    feature file (text, or PLY with vertex 'feature' or 'height'). A UserWarning says when the map marks
    more than half or less than 0.5% of the surface. Returns a ResizeResult (a mesh): V (the resized #V×3
    positions), F, parameters, and the fields of `geotex resize --report` (help(geotex.ResizeResult)):
    method (the one run: the default 'auto' runs 'axis-similarity' for a box scale, 'similarity' for any
    other deformation), detector, marked_fraction, marked_vertices, regions, warning, seconds; features
    (the weights used)."""
    V, F = _arrays(mesh, F)
    weights = path = None
    if isinstance(features, str) and features in _FEATURE_MAPS:
        options["features"] = features
    elif isinstance(features, (str, os.PathLike)):
        path = _path(features)
    else:
        weights = features
    return ResizeResult(**_geotex.resize(V, F, deformed, weights, path, options))


@with_options("FeatureMapOptions")
def feature_map(mesh: MeshLike, F: Any = None, **options: Any) -> FeatureMap:
    """The feature map of resizing (Sec. 9.4; what `geotex resize --features` and resize() use).
    Returns a FeatureMap: weights (#V in [0, 1] for 'importance', the default; in {0, 1} for the binary
    maps), field (the raw importance, or the height or ADF a binary map was grown on), detector
    (the one used; for 'auto', the one chosen), marked_fraction, marked_vertices, regions, warning
    (also raised as a UserWarning), parameters."""
    return FeatureMap(**_geotex.feature_map(*_arrays(mesh, F), options))


_FEATURE_MAPS = tuple(next(f for f in table("FeatureMapOptions")["fields"] if f["name"] == "features")["choices"])


# ------------------------------------------------------------------------------------------------
# Pictures and pages


@with_options("RenderOptions")
def render(mesh: MeshLike, F: Any = None, path: Optional[Union[str, os.PathLike]] = None, field: Any = None,
           edges: Any = None, **options: Any) -> np.ndarray:
    """A software-rendered picture (`geotex render`): returns the image as an H×W×3 uint8 array, and
    writes it as PNG when `path` is given. field: #V values shown through a colour map; edges: #S×2
    vertex pairs drawn as lines, or #E edge labels in edges() order (a result's edge_labels: the edges
    labelled above 0.5 are drawn)."""
    V, F = _arrays(mesh, F)
    return _geotex.render(V, F, None if path is None else _path(path), field, edges, options)


@with_options("ViewerOptions")
def view(meshes: Any, path: Union[str, os.PathLike] = "geotex-view.html", **options: Any) -> str:
    """Write a self-contained HTML page showing meshes side by side in 3D (`geotex view`).
    meshes: one mesh or a list; each a mesh (arrays, (V, F), trimesh, Open3D) or a dict with
    "mesh" (or "V" and "F") and optional "name", "field" (#V values), "edges" (#S×2 vertex pairs, or #E
    edge labels in edges() order as a result's edge_labels). Results that hold a mesh are meshes.
    Returns the path."""
    if not isinstance(meshes, list):
        meshes = [meshes]
    items = []
    for k, m in enumerate(meshes):
        if isinstance(m, dict):
            V, F = _arrays(m["mesh"]) if "mesh" in m else (m["V"], m["F"])
            items.append((str(m.get("name", f"mesh {k + 1}")), V, F, m.get("field"), m.get("edges")))
        else:
            V, F = _arrays(m)
            items.append((f"mesh {k + 1}", V, F, None, None))
    _geotex.view(items, _path(path), options)
    return _path(path)
