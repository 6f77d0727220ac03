"""wisp: human hairstyles from a few intuitive parameters (docs/python.md).

    import wisp
    style = wisp.Style.preset("ponytail")
    style.roots.strands = 20000            # the TOML's own names, checked on assignment
    hair = wisp.generate(style, seed=7)    # hair.points: P×3 float32 view, cm, head space
    image = wisp.render(hair, size=512)    # 512×512×3 uint8

Units are centimetres and seconds in head space (Y up, +Z forward). Every Hair array is a
numpy view of the Hair's own memory (its base is the Hair): reading one copies nothing.
Long calls (generate, render, read, write, the stages) release the GIL and take
``threads=`` (None: all cores); the same style and seed give the same arrays at any count.
"""

from __future__ import annotations

import os
import pathlib
import threading
import queue as _queue

from . import _wisp
from ._wisp import Error, Hair, Head, Masters, Roots, hair_formats, preset_names, read

__version__ = _wisp.__version__

__all__ = [
    "Error", "Style", "Head", "Hair", "Roots", "Masters", "generate", "render", "read",
    "preset_names", "hair_formats", "schema", "stages", "animate", "Animation", "Frame",
    "shading_names", "melanin_from_color", "compare",
]

_SCHEMA = {f["path"]: f for f in _wisp.schema()}
_SECTIONS = _wisp.sections()


def schema():
    """Every style field (docs/style.md) as dicts: path, type, stage, unit, paper, doc,
    range (lo, hi) where it has one, choices."""
    return _wisp.schema()


def _child(section: str, key: str) -> str:
    return f"{section}.{key}" if section else key


class _Section:
    """A section of a style (``style.solve``): its fields as attributes, by their TOML keys."""

    __slots__ = ("_style", "_path")

    def __init__(self, style: "Style", path: str):
        object.__setattr__(self, "_style", style)
        object.__setattr__(self, "_path", path)

    def __getattr__(self, key):
        if key.startswith("_"):
            raise AttributeError(key)
        return self._style._get(_child(self._path, key))

    def __setattr__(self, key, value):
        self._style._set(_child(self._path, key), value)

    def __dir__(self):
        return list(_SECTIONS.get(self._path, []))

    def to_dict(self):
        """The section's fields and sub-sections as a dict (None for unset paths)."""
        return {k: (v.to_dict() if isinstance(v, _Section) else v)
                for k in _SECTIONS.get(self._path, [])
                for v in [getattr(self, k)]}

    def __repr__(self):
        return f"<wisp.Style section [{self._path}] {self.to_dict()!r}>"


class Style:
    """A hairstyle's parameters (docs/style.md): every field has a default, so ``Style()`` is
    the default style. Fields are read and set with their TOML names, section by section
    (``style.roots.strands = 20000``, ``style.solve.stiffness = 2.5``); a value outside the
    field's type or range raises ValueError (wisp.Error) naming the field and the allowed
    range, and leaves the style unchanged. ``style.groups`` holds the constraint groups as a
    list of ``[[group]]`` tables (dicts)."""

    __slots__ = ("_s",)

    def __init__(self, _data=None):
        object.__setattr__(self, "_s", _data if _data is not None else _wisp._Style())

    @classmethod
    def preset(cls, name: str) -> "Style":
        """A shipped preset (``wisp.preset_names()``); ValueError listing them if unknown."""
        return cls(_wisp._Style.preset(name))

    @classmethod
    def from_toml(cls, path_or_text) -> "Style":
        """A style from a TOML file (a path: str ending in .toml, or os.PathLike) or from TOML
        text. Relative paths inside a file resolve against its folder, inside text against the
        current folder."""
        if isinstance(path_or_text, os.PathLike) or (
            isinstance(path_or_text, str) and "\n" not in path_or_text
            and "=" not in path_or_text and "[" not in path_or_text and path_or_text.strip()
        ):
            return cls(_wisp._Style.from_file(os.fspath(path_or_text)))
        if not isinstance(path_or_text, str):
            raise TypeError("from_toml: expected a path or TOML text, got "
                            + type(path_or_text).__name__)
        return cls(_wisp._Style.from_text(path_or_text, "TOML text", os.getcwd()))

    def to_toml(self) -> str:
        """The style as TOML that from_toml reads back to the same style."""
        return self._s.to_toml()

    def copy(self) -> "Style":
        return Style(self._s.copy())

    @property
    def groups(self):
        """The constraint groups (tie, braid, updo and comb sections expand into these) as a
        list of dicts, one ``[[group]]`` table each; assign a list to replace them."""
        return self._s.groups

    @groups.setter
    def groups(self, value):
        self._s.groups = value

    def _get(self, path):
        if path in _SCHEMA:
            return self._s.get(path)
        if path in _SECTIONS:
            return _Section(self, path)
        try:
            self._s.get(path)
        except Error as e:  # the schema's "unknown field ... (did you mean ...)"
            raise AttributeError(str(e)) from None
        raise AttributeError(path)

    def _set(self, path, value):
        if path in _SECTIONS and path not in _SCHEMA:
            raise AttributeError(f"'{path}' is a section: set its fields ({', '.join(_SECTIONS[path])})")
        self._s.set(path, value)

    def __getattr__(self, key):
        if key.startswith("_"):
            raise AttributeError(key)
        return self._get(key)

    def __setattr__(self, key, value):
        if key == "groups":
            object.__setattr__(self, key, value)
        else:
            self._set(key, value)

    def __dir__(self):
        return sorted(set(_SECTIONS[""]) | {"groups", "preset", "from_toml", "to_toml", "copy"})

    def __eq__(self, other):
        return isinstance(other, Style) and self.to_toml() == other.to_toml()

    def __repr__(self):
        name = self._s.name
        return f"<wisp.Style {name!r}>" if name else "<wisp.Style>"


def generate(style: Style | None = None, head: Head | None = None, seed: int | None = None,
             threads: int | None = None) -> Hair:
    """Grows the style's hair (roots → masters → solve → members → colour) on ``head`` (None:
    the head the style's [head] names, the built-in one by default) and returns a Hair
    (``hair.stats``: the run's figures, as ``wisp generate --stats`` writes them; ``hair.head``:
    the head). ``seed`` overrides the style's; ``threads`` None uses all cores. Releases the
    GIL. The arrays equal the CLI's files for the same style and seed at any thread count."""
    style = style if style is not None else Style()
    if not isinstance(style, Style):
        raise TypeError("generate: style must be a wisp.Style, got " + type(style).__name__)
    if head is not None and not isinstance(head, Head):
        raise TypeError("generate: head must be a wisp.Head or None, got " + type(head).__name__)
    hair, stats, used_head = _wisp.generate(style._s, head, seed, threads)
    hair.stats = stats
    hair.head = used_head
    return hair


_builtin_head = None
_builtin_lock = threading.Lock()


def _default_head(hair):
    global _builtin_head
    head = getattr(hair, "head", None)
    if head is not None:
        return head
    with _builtin_lock:
        if _builtin_head is None:
            _builtin_head = Head.builtin()
    return _builtin_head


def _head_for(where: str, head, hair: Hair):
    """A head argument as the functions take it: a Head; None, the head `hair` was generated
    on, else the built-in head; False, none (None to the extension)."""
    if head is False:
        return None
    if head is None:
        return _default_head(hair)
    if not isinstance(head, Head):
        raise TypeError(f"{where}: head must be a wisp.Head, None or False")
    return head


def render(hair: Hair, head: Head | None | bool = None, view: str = "three-quarter",
           size=1024, threads: int | None = None, alpha: bool = False, targets=None,
           **options):
    """Renders hair (and a head) as ``wisp render`` does: an H×W×3 uint8 sRGB array, or with
    ``alpha=True`` H×W×4 whose fourth channel is the coverage (0 to 255: the share of the
    pixel that hair and head cover, antialiased) and whose colours are straight (not
    premultiplied), the background left out (black where alpha is 0).

    head: a Head; None: the head the hair was generated on, else the built-in head; False:
    no head. view: one of ``wisp._wisp.view_names()`` ("front", "three-quarter", ...). size:
    N (square) or (width, height) in pixels. options, as the CLI's: eye=(x,y,z) and
    target=(x,y,z) in cm, fov (degrees), background=(r,g,b) linear, shading (one of
    ``wisp.shading_names()``: "hair", "fiber", "kajiya-kay"), specular, specular_exponent, rim
    (0 turns the rim light off), shadows (bool), width_scale.

    targets: a list of the training targets that ``wisp dataset`` writes (docs/dataset.md),
    drawn by the picture's camera: "orientation" (θ float32 in [0, π), radians from +x
    towards up), "mask" (bool), "depth" (float32, cm), "strand" (H×W×3 uint8, HairStep's strand
    map), "confidence" (float32), "matte" (float32 coverage), "strand_id" (int32, -1: none),
    "depth_hairstep" (float32). Then the result is a dict: "image" (the picture), each target,
    and the camera as OpenCV has it, "K" (3×3) and "world_to_camera" (4×4, cm), so that
    pixel = K (R p + t)."""
    if not isinstance(hair, Hair):
        raise TypeError("render: hair must be a wisp.Hair, got " + type(hair).__name__)
    head = _head_for("render", head, hair)
    if isinstance(size, (tuple, list)):
        if len(size) != 2:
            raise ValueError(f"size: expected N or (width, height), got {size!r}")
        width, height = size
    else:
        width = height = size
    for name, v in (("width", width), ("height", height)):
        if isinstance(v, bool) or not isinstance(v, int):
            raise TypeError(f"size: {name} must be an integer, got {v!r}")
    if not isinstance(alpha, bool):
        raise TypeError(f"alpha: expected True or False, got {alpha!r}")
    image = _wisp.render(hair, head, view, width, height, threads, alpha, **options)
    if targets is None:
        return image
    if isinstance(targets, str) or not all(isinstance(t, str) for t in targets):
        raise TypeError(f"targets: expected a list of map names, got {targets!r}")
    out = {"image": image}
    out.update(_wisp.targets(hair, head, view, width, height, list(targets), threads, **options))
    return out


def compare(a: Hair, b: Hair, head: Head | None | bool = None,
            views=("front", "left", "back", "right"), size: int = 256, voxel: float = 0.5,
            threads: int | None = None) -> dict:
    """How close hair ``a`` (a reconstruction) is to the reference ``b``, as ``wisp compare``:
    a dict with "strands" (precision, recall and F1 at 2 mm/20°, 3 mm/30° and 4 mm/40°),
    "chamfer_a_to_b_cm", "chamfer_b_to_a_cm", "position_error_cm" and
    "curvature_error_per_cm" (when both have as many strands, strand i the same strand),
    "orientation_error_degrees" and "silhouette_iou" over the views, and "occupancy_iou"
    (docs/dataset.md, "Comparing hair").

    head: a Head hiding the hair behind it in the views; None: b's head, else the built-in
    head; False: none. views: names of ``wisp._wisp.view_names()``. size: the views' pixels a
    side. voxel: the occupancy grid's cell, cm."""
    for name, h in (("a", a), ("b", b)):
        if not isinstance(h, Hair):
            raise TypeError(f"compare: {name} must be a wisp.Hair, got {type(h).__name__}")
    head = _head_for("compare", head, b)
    if isinstance(views, str) or not all(isinstance(v, str) for v in views):
        raise TypeError(f"compare: views must be a list of view names, got {views!r}")
    known = _wisp.view_names()
    for v in views:
        if v not in known:
            raise ValueError(f"compare: unknown view {v!r} (views: {', '.join(known)})")
    if isinstance(size, bool) or not isinstance(size, int) or not 16 <= size <= 4096:
        raise ValueError(f"compare: size must be an integer in [16, 4096], got {size!r}")
    if isinstance(voxel, bool) or not isinstance(voxel, (int, float)) or not 0.01 <= voxel <= 100:
        raise ValueError(f"compare: voxel must be a number in [0.01, 100] cm, got {voxel!r}")
    return _wisp.compare(a, b, head, list(views), size, float(voxel), threads)


def shading_names() -> list[str]:
    """The renderer's shading models, as ``render(shading=...)`` and ``wisp render --shading``
    take them."""
    return _wisp.shading_names()


def melanin_from_color(colors, beta_n: float = 0.3):
    """The eumelanin and pheomelanin concentrations (an N×2 float32 array, in Chiang et al.
    2016's units, as pbrt's) whose hair has each linear RGB colour of ``colors`` (N×3): the
    pigments the ``fiber`` shading gives a strand of that colour, for azimuthal roughness
    beta_n."""
    return _wisp.melanin_from_color(colors, beta_n)


def _repr_png_(self):
    """A small picture of the hair for Jupyter (256², three-quarter view, no shadows)."""
    image = render(self, size=256, shadows=False, rim=0)
    return _wisp.encode_png(image)


Hair._repr_png_ = _repr_png_


def _check_types(where, **args):
    """A TypeError naming ``where`` and the argument for a value that is not of its wisp type
    (rather than the extension's own signature, with its internal names)."""
    for name, (value, cls) in args.items():
        if not isinstance(value, cls):
            raise TypeError(f"{where}: {name} must be a wisp.{cls.__name__}, got "
                            + type(value).__name__)


class stages:
    """The pipeline's stages one at a time (DESIGN.md), for research use: each takes the
    outputs before it, so any one can be inspected or replaced. ``generate`` is
    roots → masters → solve → members → color with the same results. To replace a stage with
    one's own: ``wisp.Roots.from_arrays(head, master_positions, member_positions,
    wisp_offsets)`` for the roots, ``masters.replaced(outline=..., details=...)`` for the
    masters (before or after solve), ``wisp.Hair.from_arrays`` for the members."""

    @staticmethod
    def roots(style: Style, head: Head, threads=None) -> Roots:
        """Master and member roots on the scalp (§2.3)."""
        _check_types("stages.roots", style=(style, Style), head=(head, Head))
        return _wisp.stage_roots(style._s, head, threads)

    @staticmethod
    def masters(style: Style, head: Head, roots: Roots, threads=None) -> Masters:
        """Master strands synthesized from the prototype (§2.2), unsolved."""
        _check_types("stages.masters", style=(style, Style), head=(head, Head),
                     roots=(roots, Roots))
        return _wisp.stage_masters(style._s, head, roots, threads)

    @staticmethod
    def solve(style: Style, head: Head, roots: Roots, masters: Masters, threads=None):
        """The styling field, density collisions and constraints (§3, §4, Algorithm 1) on a
        copy of masters: returns (solved Masters, solver stats dict)."""
        _check_types("stages.solve", style=(style, Style), head=(head, Head),
                     roots=(roots, Roots), masters=(masters, Masters))
        return _wisp.stage_solve(style._s, head, roots, masters, threads)

    @staticmethod
    def members(style: Style, head: Head, roots: Roots, masters: Masters, threads=None) -> Hair:
        """Every member strand (§2.1), cut and pushed out of the head; no colours yet."""
        _check_types("stages.members", style=(style, Style), head=(head, Head),
                     roots=(roots, Roots), masters=(masters, Masters))
        return _wisp.stage_members(style._s, head, roots, masters, threads)

    @staticmethod
    def color(style: Style, hair: Hair, threads=None) -> Hair:
        """A colour per strand (§5), in place; returns hair."""
        _check_types("stages.color", style=(style, Style), hair=(hair, Hair))
        _wisp.stage_color(style._s, hair, threads)
        return hair


class Frame(tuple):
    """One frame of an animation: (index, time in s, points P×3 float32 in cm, world space,
    head rotation 3×3, head translation 3 in cm)."""

    __slots__ = ()

    index = property(lambda self: self[0])
    time = property(lambda self: self[1])
    points = property(lambda self: self[2])
    head_rotation = property(lambda self: self[3])
    head_translation = property(lambda self: self[4])


class Animation:
    """The frames of ``wisp.animate``, computed in a worker thread as they are taken (at most
    ``buffer`` ahead). After the last frame, ``stats`` holds the run's figures (as ``wisp
    animate --stats`` writes them) and ``rest`` the rest hair."""

    def __init__(self, run, buffer=2):
        self.stats = None
        self.rest = None
        self._run = run
        self._buffer = buffer

    def __iter__(self):
        frames = _queue.Queue(maxsize=self._buffer)
        done = object()
        stop = threading.Event()
        error = []

        def on_frame(*frame):
            if stop.is_set():
                raise GeneratorExit("animation closed")
            while True:
                try:
                    frames.put(Frame(frame), timeout=0.1)
                    return
                except _queue.Full:
                    if stop.is_set():
                        raise GeneratorExit("animation closed")

        def work():
            try:
                stats = self._run(on_frame)
                self.rest = stats.pop("rest")
                self.stats = stats
            except BaseException as e:  # handed to the consumer below
                error.append(e)
            finally:
                frames.put(done)

        worker = threading.Thread(target=work, name="wisp.animate", daemon=True)
        worker.start()
        try:
            while True:
                item = frames.get()
                if item is done:
                    break
                yield item
        finally:
            stop.set()
            while worker.is_alive():
                try:
                    frames.get(timeout=0.1)
                except _queue.Empty:
                    pass
            worker.join()
        if error and not isinstance(error[0], GeneratorExit):
            raise error[0]


def animate(style_or_hair, motion: str = "lean", frames: int = 48, fps: float = 24,
            head: Head | None = None, seed: int | None = None,
            threads: int | None = None, ties=None) -> Animation:
    """Animates a style's hair (generated first, its ties held) or a Hair with the Adaptive
    Wisp Tree (Bertails et al. 2003), as ``wisp animate`` does. motion: a preset ("lean",
    "shake", "nod", "jump", "run") or a keyframe JSON path. ties: as ``wisp animate --tie``,
    points (x, y, z) or (x, y, z, radius) in cm, in the rest hair's coordinates (radius 2 by
    default; a T×3 or T×4 array works too): every strand passing within radius of a point is
    held rigidly to the head from its root to there, like a ponytail's tie. Returns an
    Animation: iterate it for Frame tuples (index, time, points, head_rotation,
    head_translation); its ``stats`` are set once the last frame is taken. Argument errors
    raise here, an unknown motion among them; a motion file that does not read, or a tie that
    passes near no strand, raises when the first frame is taken."""
    if isinstance(style_or_hair, Style):
        style, hair = style_or_hair, None
    elif isinstance(style_or_hair, Hair):
        style, hair = Style(), style_or_hair
        head = head if head is not None else getattr(hair, "head", None)
    else:
        raise TypeError("animate: expected a wisp.Style or a wisp.Hair, got "
                        + type(style_or_hair).__name__)
    for name, v in (("frames", frames),):
        if isinstance(v, bool) or not isinstance(v, int):
            raise TypeError(f"{name}: expected an integer, got {v!r}")
    if not 1 <= frames <= 100000:
        raise ValueError(f"frames: expected 1 to 100000, got {frames}")
    if not isinstance(fps, (int, float)) or not 0 < fps <= 1000:
        raise ValueError(f"fps: expected a number in (0, 1000], got {fps!r}")
    if head is not None and not isinstance(head, Head):
        raise TypeError("animate: head must be a wisp.Head or None")
    if isinstance(motion, os.PathLike):
        motion = os.fspath(motion)
    if not isinstance(motion, str):
        raise TypeError("animate: motion must be a preset name or a motion file path, got "
                        + type(motion).__name__)
    if motion not in _wisp.motion_names() and not os.path.isfile(motion):
        raise ValueError(f"motion: {motion!r} is neither a motion preset ("
                         + ", ".join(_wisp.motion_names()) + ") nor a motion file")
    _wisp.check_ties(ties)

    def run(on_frame):
        return _wisp.animate(style._s, hair, head, motion, frames, float(fps), seed, threads,
                             ties, on_frame)

    return Animation(run)
