"""rodsim: Cosserat rod scenes from Python, on the C library (rodsim.h).

    import rodsim
    with rodsim.Scene("scenes/needle_lift.ini", overrides={"solver.duration": 1}) as s:
        s.run()                      # to solver.duration, as `rodsim run` steps it
        st = s.state()               # dict of numpy arrays (SI units)
        print(st["t"], st["tip_force"])

A scene of several rods ([rod NAME]) is stepped as `rodsim run` steps it;
s.rods lists their names, and the calls that read or drive a rod take
rod=NAME (s.state(rod="upper"), s.set_end_pose("tip", p, rod="upper")).
Without it they address the first rod, as for a scene of one rod.

The library is found through the environment variable RODSIM_LIBRARY (a
path to librodsim.so), else next to this package (a build copy, or a
checkout's build/release), else the system's (librodsim.so.1).
Units are SI (m, s, N, N m, rad); arrays are numpy float64.
"""
import ctypes
import ctypes.util
import os

import numpy as np

__all__ = ["Scene", "Error", "api_version", "library_path"]

_MAJOR = 1  # the major of rodsim.h this package speaks
_MINOR = 2  # the least minor it needs (1: several rods; 2: rodsim_node_arc)

# rodsim_status and rodsim_field (rodsim.h)
_STATUS = {0: "ok", 1: "bad_input", 2: "unstable", 3: "no_convergence", 4: "failed"}
_POSITIONS, _DIRECTORS, _VELOCITIES, _FORCES = 0, 1, 2, 3
_ENDS = {"root": 0, "tip": 1}


class Error(Exception):
    """A failure of the library: str(e) is its message (a bad scene's is the
    one `rodsim run` prints after "rodsim run: "); e.status names the kind:
    bad_input, unstable, no_convergence or failed."""

    def __init__(self, message, status="failed"):
        super().__init__(message)
        self.status = status


def _candidates():
    env = os.environ.get("RODSIM_LIBRARY")
    if env:
        return [env]
    here = os.path.dirname(os.path.abspath(__file__))
    names = ["librodsim.so.%d" % _MAJOR, "librodsim.so"]
    found = [os.path.join(here, n) for n in names]
    # a checkout: python/rodsim/ next to build/release/
    found += [os.path.join(here, "..", "..", "build", "release", n) for n in names]
    found = [p for p in found if os.path.exists(p)]
    system = ctypes.util.find_library("rodsim")
    return found + [system or "librodsim.so.%d" % _MAJOR]


def _load():
    tried = []
    for path in _candidates():
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append("%s (%s)" % (path, e))
            continue
        _declare(lib)
        major = lib.rodsim_api_version() // 1000
        if major != _MAJOR or lib.rodsim_api_version() % 1000 < _MINOR:
            raise ImportError("rodsim: %s speaks rodsim.h version %d.%d, this package %d.%d "
                              "or a later minor" % (path, major, lib.rodsim_api_version() % 1000,
                                                    _MAJOR, _MINOR))
        return lib, path
    raise ImportError("rodsim: librodsim.so not found; build it (make lib) and set "
                      "RODSIM_LIBRARY=build/release/librodsim.so, or make install. Tried: "
                      + "; ".join(tried))


def _declare(lib):
    c_scene = ctypes.c_void_p
    dbl, dblp = ctypes.c_double, ctypes.POINTER(ctypes.c_double)
    sig = {
        "rodsim_api_version": (ctypes.c_int, []),
        "rodsim_load_file": (ctypes.c_int, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p),
                                            ctypes.c_int, ctypes.POINTER(c_scene)]),
        "rodsim_load_text": (ctypes.c_int, [ctypes.c_char_p, ctypes.c_char_p,
                                            ctypes.POINTER(ctypes.c_char_p), ctypes.c_int,
                                            ctypes.POINTER(c_scene)]),
        "rodsim_free": (None, [c_scene]),
        "rodsim_last_error": (ctypes.c_char_p, [c_scene]),
        "rodsim_nodes": (ctypes.c_int, [c_scene]),
        "rodsim_time": (dbl, [c_scene]),
        "rodsim_dt": (dbl, [c_scene]),
        "rodsim_duration": (dbl, [c_scene]),
        "rodsim_frame_rate": (dbl, [c_scene]),
        "rodsim_length": (dbl, [c_scene]),
        "rodsim_step": (ctypes.c_int, [c_scene, dbl]),
        "rodsim_run": (ctypes.c_int, [c_scene, dbl]),
        "rodsim_field_size": (ctypes.c_size_t, [c_scene, ctypes.c_int]),
        "rodsim_get": (ctypes.c_int, [c_scene, ctypes.c_int, dblp, ctypes.c_size_t]),
        "rodsim_view": (dblp, [c_scene, ctypes.c_int]),
        "rodsim_end_load": (ctypes.c_int, [c_scene, ctypes.c_int, dblp, dblp]),
        "rodsim_knot_type": (ctypes.c_int, [c_scene, ctypes.c_char_p, ctypes.c_size_t]),
        "rodsim_set_end_pose": (ctypes.c_int, [c_scene, ctypes.c_int, dblp, dblp]),
        "rodsim_set_tip_load": (ctypes.c_int, [c_scene, dblp, dblp]),
        "rodsim_state_size": (ctypes.c_size_t, [c_scene]),
        "rodsim_save": (ctypes.c_int, [c_scene, ctypes.c_void_p, ctypes.c_size_t]),
        "rodsim_restore": (ctypes.c_int, [c_scene, ctypes.c_void_p, ctypes.c_size_t]),
        "rodsim_render": (ctypes.c_int, [c_scene, ctypes.c_char_p]),
        "rodsim_rod_count": (ctypes.c_int, [c_scene]),
        "rodsim_rod_name": (ctypes.c_char_p, [c_scene, ctypes.c_int]),
        "rodsim_rod_index": (ctypes.c_int, [c_scene, ctypes.c_char_p]),
        "rodsim_rod_nodes": (ctypes.c_int, [c_scene, ctypes.c_int]),
        "rodsim_get_rod": (ctypes.c_int, [c_scene, ctypes.c_int, ctypes.c_int, dblp,
                                          ctypes.c_size_t]),
        "rodsim_node_arc": (ctypes.c_int, [c_scene, ctypes.c_int, dblp, ctypes.c_size_t]),
        "rodsim_end_load_rod": (ctypes.c_int, [c_scene, ctypes.c_int, ctypes.c_int, dblp, dblp]),
        "rodsim_set_end_pose_rod": (ctypes.c_int, [c_scene, ctypes.c_int, ctypes.c_int, dblp,
                                                   dblp]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name, None)
        if f is None:  # an older minor: refused by _load
            continue
        f.restype, f.argtypes = res, args


_lib, library_path = _load()


def api_version():
    """The library's rodsim.h version, (major, minor)."""
    v = _lib.rodsim_api_version()
    return v // 1000, v % 1000


def _vec3(values, what):
    a = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    if a.size != 3:
        raise Error("%s: 3 numbers expected, not %d" % (what, a.size), "bad_input")
    return a


def _ptr(a):
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def _override_text(key, value):
    if isinstance(value, (list, tuple, np.ndarray)):
        value = " ".join(repr(float(v)) for v in value)
    elif isinstance(value, bool):
        value = "true" if value else "false"
    elif isinstance(value, float):
        value = repr(value)
    return "%s=%s" % (key, value)


def _closed(*args):
    raise Error("the scene is closed", "bad_input")


class Scene:
    """A rod scene loaded from a file or from INI text, stepped in time.

    Scene(path_or_ini_text, overrides=None): a path (os.PathLike), or a
    string naming an existing file or ending in .ini, is read as a file; any
    other string as the scene's INI text (name: its name in messages and
    the video's file name). overrides: {"section.key": value} (or a list of
    "section.key=value"), applied in order as `rodsim run --set` does; a
    list or array value is written as numbers separated by spaces.
    Raises rodsim.Error with `rodsim run`'s message for a bad scene.
    """

    def __init__(self, scene, overrides=None, name=None):
        self._h = None
        self._step = _closed
        if isinstance(overrides, dict):
            sets = [_override_text(k, v) for k, v in overrides.items()]
        else:
            sets = list(overrides or [])
        arr = (ctypes.c_char_p * max(1, len(sets)))(*[s.encode() for s in sets])
        handle = ctypes.c_void_p()
        is_path = isinstance(scene, os.PathLike)
        scene = os.fspath(scene)
        if is_path or ("\n" not in scene and (os.path.exists(scene) or scene.endswith(".ini"))):
            st = _lib.rodsim_load_file(scene.encode(), arr, len(sets), ctypes.byref(handle))
        else:
            st = _lib.rodsim_load_text((name or "scene").encode(), scene.encode(), arr,
                                       len(sets), ctypes.byref(handle))
        if st != 0:
            raise Error(_lib.rodsim_last_error(None).decode(), _STATUS.get(st, "failed"))
        self._h = handle
        self.nodes = _lib.rodsim_nodes(handle)   # NS
        self.dt = _lib.rodsim_dt(handle)         # s, solver.dt
        self.duration = _lib.rodsim_duration(handle)  # s, solver.duration
        self.frame_rate = _lib.rodsim_frame_rate(handle)  # output frames per simulated s
        self.length = _lib.rodsim_length(handle)  # m
        # the rods' names, in the scene's order ("rod" for a bare [rod])
        self.rods = [_lib.rodsim_rod_name(handle, k).decode()
                     for k in range(_lib.rodsim_rod_count(handle))]
        self._step = _lib.rodsim_step
        self._pose = np.zeros(6)
        self._load = np.zeros(6)

    # -- life ---------------------------------------------------------------
    def close(self):
        """Frees the scene (also at the end of a with block); idempotent."""
        if self._h is not None:
            _lib.rodsim_free(self._h)
            self._h = None
            self._step = _closed

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # at interpreter exit the library may be gone
            pass

    def _handle(self):
        if self._h is None:
            raise Error("the scene is closed", "bad_input")
        return self._h

    def _check(self, status):
        if status != 0:
            raise Error(_lib.rodsim_last_error(self._h).decode(), _STATUS.get(status, "failed"))

    # -- stepping -----------------------------------------------------------
    @property
    def t(self):
        """The state's time, s."""
        return _lib.rodsim_time(self._handle())

    def step(self, dt=None):
        """Advances by dt (s; None: one step of solver.dt) in equal steps no
        longer than solver.dt. Raises Error (the state is the one before)."""
        st = self._step(self._h, dt if dt is not None else 0.0)
        if st:
            self._check(st)

    def run(self, until=None):
        """Advances to the time `until` (s; None: solver.duration) as
        `rodsim run` does, frame interval by frame interval."""
        self._check(_lib.rodsim_run(self._handle(), -1.0 if until is None else float(until)))

    # -- reading ------------------------------------------------------------
    def _rod(self, rod):
        """The index of the rod named `rod` (None: 0, the first rod); Error
        (bad_input) naming the scene's rods for another name."""
        if rod is None:
            return 0
        k = _lib.rodsim_rod_index(self._handle(), str(rod).encode())
        if k < 0:
            raise Error(_lib.rodsim_last_error(self._h).decode(), "bad_input")
        return k

    def _field(self, field, shape, rod=0):
        out = np.empty(shape)
        self._check(_lib.rodsim_get_rod(self._handle(), rod, field, _ptr(out), out.size))
        return out

    def positions(self, rod=None):
        """NS x 3, m, global (rod: its name in a scene of several rods)."""
        k = self._rod(rod)
        return self._field(_POSITIONS, (_lib.rodsim_rod_nodes(self._h, k), 3), k)

    def arc(self, rod=None):
        """The nodes' arc lengths from the root, s_i (NS, m, at rest; rod:
        its name in a scene of several rods): i L / (NS - 1) on a uniform
        grid, the segments' rest lengths summed on a graded one (rod.refine),
        the s of `rodsim run`'s CSV."""
        k = self._rod(rod)
        out = np.empty(_lib.rodsim_rod_nodes(self._h, k))
        self._check(_lib.rodsim_node_arc(self._h, k, _ptr(out), out.size))
        return out

    def state(self, rod=None):
        """The state as numpy arrays (copies): t (s), arc (NS, m: each
        node's arc length from the root, the graded grid's on one, as
        arc()), positions (NS x 3, m),
        directors (NS x 3 x 3, rows d1 d2 d3, global), velocities (NS x 3,
        m/s), forces (NS x 3, N: the internal force, the CSV's nx,ny,nz),
        and for each end the force (N) and moment (N m) the rod exerts on
        what holds it: root_force, root_moment, tip_force, tip_moment.
        rod: the rod's name in a scene of several rods (None: the first);
        an unknown name raises Error naming the scene's rods."""
        h = self._handle()
        r = self._rod(rod)
        n = _lib.rodsim_rod_nodes(h, r)
        out = {"t": _lib.rodsim_time(h),
               "arc": self.arc(rod),
               "positions": self._field(_POSITIONS, (n, 3), r),
               "directors": self._field(_DIRECTORS, (n, 3, 3), r),
               "velocities": self._field(_VELOCITIES, (n, 3), r),
               "forces": self._field(_FORCES, (n, 3), r)}
        for end, k in _ENDS.items():
            f, m = np.empty(3), np.empty(3)
            self._check(_lib.rodsim_end_load_rod(h, r, k, _ptr(f), _ptr(m)))
            out[end + "_force"], out[end + "_moment"] = f, m
        return out

    def end_load(self, end="tip", rod=None):
        """(force N, moment N m) the rod exerts on what holds `end` (rod:
        its name in a scene of several rods)."""
        f, m = np.empty(3), np.empty(3)
        r = self._rod(rod)
        self._check(_lib.rodsim_end_load_rod(self._handle(), r, _ENDS[end], _ptr(f), _ptr(m)))
        return f, m

    def knot_type(self):
        """The centreline's knot type ("unknot", "trefoil, right-handed", ...)."""
        buf = ctypes.create_string_buffer(128)
        self._check(_lib.rodsim_knot_type(self._handle(), buf, len(buf)))
        return buf.value.decode()

    # -- driving ------------------------------------------------------------
    def set_end_pose(self, end, position, rotvec=None, rod=None):
        """Drives a held end ("root" or "tip") to position (m) and, for a
        clamped end, rotation vector rotvec (rad, from its starting frame),
        reached at the end of the next step() or run(). rod: the rod's name
        in a scene of several rods (None: the first)."""
        r = self._rod(rod)
        pose = self._pose
        pose[:3] = _vec3(position, "position")
        rot = None
        if rotvec is not None:
            pose[3:] = _vec3(rotvec, "rotvec")
            rot = _ptr(pose[3:])
        self._check(_lib.rodsim_set_end_pose_rod(self._handle(), r, _ENDS[end], _ptr(pose), rot))

    def set_tip_load(self, force=(0, 0, 0), moment=(0, 0, 0)):
        """Loads on a free tip from the next step on (N, N m, on tip.frame)."""
        self._load[:3] = _vec3(force, "force")
        self._load[3:] = _vec3(moment, "moment")
        self._check(_lib.rodsim_set_tip_load(self._handle(), _ptr(self._load),
                                             _ptr(self._load[3:])))

    # -- saving and drawing -------------------------------------------------
    def save(self):
        """The state as bytes; restore(b) puts it back exactly."""
        size = _lib.rodsim_state_size(self._handle())
        buf = ctypes.create_string_buffer(size)
        self._check(_lib.rodsim_save(self._h, buf, size))
        return buf.raw

    def restore(self, blob):
        buf = ctypes.create_string_buffer(bytes(blob), len(blob))
        self._check(_lib.rodsim_restore(self._handle(), buf, len(blob)))

    def render(self, out_dir):
        """Writes the frames recorded so far as out_dir/NAME.mp4 and the
        poster out_dir/NAME.png, as `rodsim run` draws them."""
        self._check(_lib.rodsim_render(self._handle(), os.fspath(out_dir).encode()))
