"""What the library shows of a few runs, recorded to compare two builds bit for bit.

    python tools/machine_trace.py --save before.trace      # with one library
    python tools/machine_trace.py --compare before.trace   # with another: exit 1 on a difference
    python tools/machine_trace.py --harness ...            # also the step traces of tests/harness

Each scenario compiles a program on core 0 and records, as raw bytes: the tool path
(GetToolpath), GetGCodeRunTime, what the driver callbacks were given (the simulation's
DriverGFunc also with the GetPos of that moment), and the offline machine's GetPos
(SIMPLE_GM_PARAMS and GM_PARAMS_ENHANCED) and status after every step of its stepped
clock (ToolChainCore_TestClock: deterministic, no sleeping). The scenarios: the
bundled sample program with and without tool radius compensation (simulation 10 and
20, a run 30); waiting, continuous and start/stop addCode M functions answered later,
a dwell, M0, a stop and continue, backward (32), regimes 31 and 33; the output stage
(spline, IIR filter) with a changing override and the dynamic G41/G42 correction; a
breakpoint; a manual move, connections and ResetCNC; a dense path with continuous M
functions filling the look-ahead ring.

With --harness the offline machine's pure step (tests/harness, built from the
sources of this tree: no threads, every 100 us step) is recorded too: the step
records and the place on the program after runs forward, stopped, backward.

The library is SF_TCH_LIBRARY's, else the installed one's (sf_tch.library.load()).
"""
import argparse
import ctypes
import gzip
import hashlib
import math
import pickle
import sys
import time
from pathlib import Path

from sf_tch import abi, default_ini, library

ROOT = Path(__file__).resolve().parents[1]
CORE = 0
KEY = abi.TC_TEST_CLOCK_KEY
INI = default_ini().encode()
DEMO = (ROOT / "python" / "sf_tch" / "data" / "demo.nc").read_bytes()
MOVING = (30, 31, 32, 33, 40, 41, 50, 70, 80, 90)


def doubles(*values):
    return (ctypes.c_double * max(1, len(values)))(*values)


class Recorder:
    def __init__(self, lib):
        self.lib = lib
        self.items = []
        self.answers = {}               # M -> DriverMFunc's answer
        self.pending = None             # an M answered TC_MFUNC_LATER, not confirmed yet
        self.in_sim = False
        self.fns = {
            abi.CB_DRIVER_INITIALIZE: abi.DriverInitialize(self._init),
            abi.CB_DRIVER_G_FUNC: abi.DriverGFunc(self._g),
            abi.CB_DRIVER_M_FUNC: abi.DriverMFunc(self._m),
            abi.CB_DRIVER_END: abi.DriverEnd(self._end),
        }

    def install(self):
        for number, fn in self.fns.items():
            assert self.lib.ToolChainCore_SetCallBack(CORE, number, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0

    def add(self, *item):
        self.items.append(item)

    def getpos(self):
        pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
        assert self.lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), ctypes.byref(enh)) == 0
        return bytes(pos) + bytes(enh)

    def _init(self, user, params, n, mode):
        self.add("init", mode, bytes(ctypes.string_at(params, 8 * n)) if n else b"")
        return 0

    def _g(self, user, part):
        # the simulation publishes GetPos in its own order; the machine's pacer may
        # be stepping while the notifier calls: its GetPos is recorded after each step
        self.add("G", bytes(part.contents), self.getpos() if self.in_sim else b"")
        return 0

    def _m(self, user, part):
        m = part.contents.m_func
        self.add("M", bytes(part.contents), self.getpos() if self.in_sim else b"")
        answer = self.answers.get(m, 0)
        if answer == abi.TC_MFUNC_LATER and not self.in_sim:
            self.pending = m
        return answer

    def _end(self, user):
        self.add("end")
        return 0


def fresh(lib, **fields):
    """Core 0 as a test leaves it: the INI, known motion classes, the stepped clock."""
    lib.ToolChainCore_DestroyCNC(CORE)
    assert lib.ToolChainCore_ResetCNC(CORE, 0, 10, doubles(*[0.0] * 10)) == 0
    assert lib.ToolChainCore_LoadFromIni(CORE, INI, None) == 0
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    p.calcTime = 1
    for k in range(1, 6):
        p.motion[k].acc = p.motion[k].dec = 500.0
        p.motion[k].rampType = 1
    p.motion[0].feed, p.motion[0].acc, p.motion[0].dec = 10000.0, 500.0, 500.0
    p.motion[6].dec, p.motion[6].rampType = 1000.0, 1
    p.maxConnectionDistance = 1000.0
    radius = fields.pop("radius", 0.0)
    for k in range(8):
        p.correction[k].size = radius
    for name, value in fields.items():
        setattr(p, name, value)
    assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_SetRelFeed(CORE, 1.0) == 0
    for kind in (abi.TC_SMOOTHING_IIR, abi.TC_SMOOTHING_SPLINE):
        assert lib.ToolChainCore_SetSmoothing(CORE, kind, doubles(0, 0, 0, 0)) == 0
    assert lib.ToolChainCore_TestClock(CORE, KEY, 0.0) == 0
    rec = Recorder(lib)
    rec.install()
    return rec


def wait_idle(lib, limit=30.0):
    deadline = time.monotonic() + limit
    while lib.ToolChainCore_StatusCNC(CORE) in (1, 10, 20):
        assert time.monotonic() < deadline, "stuck"
        time.sleep(0.0005)
    return lib.ToolChainCore_StatusCNC(CORE)


def compile_(lib, rec, text, window=0):
    lib.ToolChainCore_SetLookAhead(CORE, window)
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"m.nc", text) == 0
    rec.add("compiled", wait_idle(lib))
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 0, info.m_fullError
    total = ctypes.c_uint64()
    assert lib.ToolChainCore_GetToolpath(CORE, None, 0, 0, ctypes.byref(total)) == 0
    out = (abi.TC_TOOLPATH_RECORD * total.value)()
    assert lib.ToolChainCore_GetToolpath(CORE, out, total.value, 0, ctypes.byref(total)) == 0
    rec.add("toolpath", bytes(out))


def simulate(lib, rec, regime=10):
    rec.in_sim = True
    assert lib.ToolChainCore_StartCNCEx(CORE, regime, None) == 0
    status = wait_idle(lib)
    rec.in_sim = False
    rec.add("simulated", regime, status, rec.getpos(),
            lib.ToolChainCore_GetGCodeRunTime(CORE, lib.ToolChainCore_FileToIdx(CORE, b"m.nc")))


def confirm(lib, rec):
    """ConfirmMFunc of the M answered later (retried until the handshake holds it)."""
    deadline = time.monotonic() + 10.0
    while lib.ToolChainCore_ConfirmMFunc(CORE) != 0:
        assert time.monotonic() < deadline, "no M function waits"
        time.sleep(0.0005)
    rec.add("confirmed", rec.pending)
    rec.pending = None


def poll(lib, rec, dt=0.01, limit=300.0, on_step=None, confirm_after=3):
    """Steps the machine while it moves; GetPos and the status after every step. An M
    answered later is confirmed `confirm_after` steps after the machine stands at it;
    while the worker sends addCode's M functions (70, 80, 90: no machine time runs)
    it is confirmed once GetPos shows it waiting, the worker followed in real time."""
    t, n, stood = 0.0, 0, 0
    while True:
        status = lib.ToolChainCore_StatusCNC(CORE)
        if status not in MOVING:
            break
        if status in (70, 80, 90):
            if rec.pending is None:
                time.sleep(0.0002)
                continue
            deadline = time.monotonic() + 10.0
            pos = abi.SIMPLE_GM_PARAMS()
            while True:
                assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
                if pos.m_func == rec.pending + 10000:
                    break
                assert time.monotonic() < deadline, "the addCode M is not shown waiting"
                time.sleep(0.0002)
            rec.add("waiting", status, rec.getpos())
            confirm(lib, rec)
            continue
        assert t < limit, "the run does not end"
        if on_step is not None:
            on_step(n)
        if rec.pending is not None:
            stood += 1
            if stood > confirm_after:
                confirm(lib, rec)
                stood = 0
        assert lib.ToolChainCore_TestClock(CORE, KEY, dt) == 0
        t += dt
        n += 1
        rec.add("pos", lib.ToolChainCore_StatusCNC(CORE), rec.getpos())
    rec.add("halted", lib.ToolChainCore_StatusCNC(CORE), rec.getpos())


def steps(lib, rec, count, dt=0.01):
    """`count` steps of the machine, GetPos after each (a run that is to be stopped)."""
    for _ in range(count):
        assert lib.ToolChainCore_TestClock(CORE, KEY, dt) == 0
        rec.add("pos", lib.ToolChainCore_StatusCNC(CORE), rec.getpos())


def start(lib, rec, regime=30, add_code=None):
    rc = lib.ToolChainCore_StartCNCEx(CORE, regime, add_code)
    rec.add("start", regime, rc)


# ------------------------------------------------------------------ the scenarios

def demo(lib, radius):
    rec = fresh(lib, radius=radius)
    compile_(lib, rec, DEMO)
    simulate(lib, rec, 10)
    simulate(lib, rec, 20)
    start(lib, rec)
    poll(lib, rec)
    return rec.items


M_PROGRAM = (b"G0 X5 Y5\nM7\nG1 X20 F3000\nM1010\nG1 Y20\nG4 H0.15\nG2 X40 Y20 I10 J0\nM0\n"
             b"G1 X60 F6000\nM8\nG1 Y60\nG3 X40 Y80 I-20 J0\nG1 X0 Y80\nM9\nG1 X0 Y0\n")


def m_functions(lib):
    rec = fresh(lib)
    compile_(lib, rec, M_PROGRAM)
    simulate(lib, rec, 10)
    rec.answers = {7: abi.TC_MFUNC_LATER, 3: abi.TC_MFUNC_LATER, 8: abi.TC_MFUNC_LATER, 4: abi.TC_MFUNC_LATER}
    start(lib, rec, 30, b"M3")              # the start's M answered later
    poll(lib, rec)                          # the waiting M7 answered later; stands at M0 (-33)
    start(lib, rec, 30)
    steps(lib, rec, 25)
    rec.add("stop", lib.ToolChainCore_StopCNCEx(CORE, b"M5 M9"))
    poll(lib, rec)
    start(lib, rec, 32)                     # backward a while, stopped
    steps(lib, rec, 40)
    rec.add("stop", lib.ToolChainCore_StopCNCEx(CORE, None))
    poll(lib, rec)
    start(lib, rec, 31)                     # forward without M functions, stopped
    steps(lib, rec, 30)
    rec.add("stop", lib.ToolChainCore_StopCNCEx(CORE, None))
    poll(lib, rec)
    start(lib, rec, 33)                     # on to the end (M8 answered later)
    poll(lib, rec)
    start(lib, rec, 32)                     # back to the start
    poll(lib, rec)
    start(lib, rec, 33, b"M4")              # the start's M answered later; M7 skipped
    poll(lib, rec)
    start(lib, rec, 30)                     # after M0: M8 answered later, stopped while it waits
    while rec.pending is None and lib.ToolChainCore_StatusCNC(CORE) == 30:
        steps(lib, rec, 1)
    steps(lib, rec, 3)
    rec.add("stop", lib.ToolChainCore_StopCNCEx(CORE, None))
    rec.pending = None                      # the stop answered it
    poll(lib, rec)
    return rec.items


def output_stage(lib):
    rec = fresh(lib, radius=1.5, dynamicG41Correction_mm=0.2, dynamicG42Correction_percent=10.0)
    assert lib.ToolChainCore_SetSmoothing(CORE, abi.TC_SMOOTHING_SPLINE, doubles(60, 1e6, 0, 0)) == 0
    compile_(lib, rec, DEMO)
    start(lib, rec)

    def override(n):
        if n == 100:
            lib.ToolChainCore_SetRelFeed(CORE, 1.6)
        elif n == 400:
            lib.ToolChainCore_SetRelFeed(CORE, 0.4)
        elif n == 600:
            lib.ToolChainCore_SetRelFeed(CORE, 1.0)
    poll(lib, rec, dt=0.01, on_step=override)
    assert lib.ToolChainCore_SetSmoothing(CORE, abi.TC_SMOOTHING_SPLINE, doubles(0, 0, 0, 0)) == 0
    assert lib.ToolChainCore_SetSmoothing(CORE, abi.TC_SMOOTHING_IIR, doubles(2.0e6, 1.0e6, 0.05e6, 3)) == 0
    rec.add("reset", lib.ToolChainCore_ResetCNC(CORE, 0, 10, doubles(*[0.0] * 10)), rec.getpos())
    start(lib, rec)
    poll(lib, rec, dt=0.01)
    return rec.items


def breakpoint_(lib):
    rec = fresh(lib)
    text = b"G1 X100 F6000\nG1 Y50\nG1 X0\nG1 Y0\n"
    compile_(lib, rec, text)
    assert lib.ToolChainCore_SetBreakpoint(CORE, 3, lib.ToolChainCore_FileToIdx(CORE, b"m.nc")) == 0
    start(lib, rec)
    poll(lib, rec, dt=0.005)
    start(lib, rec)
    poll(lib, rec, dt=0.005)
    assert lib.ToolChainCore_SetBreakpoint(CORE, 0, 0) == 0
    return rec.items


SQUARE = b"G0 X0 Y0\nG1 X100 F3000\nG1 Y100\nG1 X0\nG1 Y0\nM8\nG0 X10 Y10\n"


def manual_and_connect(lib):
    rec = fresh(lib)
    compile_(lib, rec, SQUARE)
    start(lib, rec)
    steps(lib, rec, 150)
    rec.add("stop", lib.ToolChainCore_StopCNCEx(CORE, None))
    poll(lib, rec)
    rec.add("goto", lib.ToolChainCore_GoToPosition(CORE, 2, doubles(50.0, 50.0)))
    poll(lib, rec)
    rec.add("connect", lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(50.0, 50.0), None, 0, 0, 2))
    poll(lib, rec)
    rec.add("goto", lib.ToolChainCore_GoToPosition(CORE, 2, doubles(70.0, 20.0)))
    poll(lib, rec)
    rec.add("connect", lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 10, 2, doubles(70.0, 20.0), b"M7", 0, 0, 0))
    poll(lib, rec)
    start(lib, rec, 32)
    poll(lib, rec)
    rec.add("connect", lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 11, 1, doubles(4.0), None, 0, 0x3FF, 0))
    poll(lib, rec)
    rec.add("reset", lib.ToolChainCore_ResetCNC(CORE, 0, 3, doubles(30.0, -20.0, 1.0)), rec.getpos())
    start(lib, rec)
    poll(lib, rec)
    rec.add("destroy", lib.ToolChainCore_DestroyCNC(CORE), rec.getpos())
    return rec.items


def dense(lib):
    rec = fresh(lib)
    n, r = 300, 20.0
    pts = [(r * math.cos(2 * math.pi * i / n), r * math.sin(2 * math.pi * i / n)) for i in range(n + 1)]
    text = f"G0 X{pts[0][0]:.6f} Y{pts[0][1]:.6f}\n" + "".join(
        f"G1 X{x:.6f} Y{y:.6f} F6000{' M1001' if i % 3 == 0 else ''}\n" for i, (x, y) in enumerate(pts[1:]))
    compile_(lib, rec, text.encode(), window=20)
    simulate(lib, rec, 10)
    start(lib, rec)
    poll(lib, rec, dt=0.002)
    return rec.items


SCENARIOS = {"demo": lambda lib: demo(lib, 0.0), "demo_comp": lambda lib: demo(lib, 2.0),
             "m_functions": m_functions, "output_stage": output_stage, "breakpoint": breakpoint_,
             "manual_and_connect": manual_and_connect, "dense": dense}


# ------------------------------------------------------------------ the harness's step

def harness_traces():
    sys.path.insert(0, str(ROOT / "tests"))
    import harness
    from test_machine import ARCS, LINES, SQUARE_G42, circle_chords, params
    mh = harness.load()
    out = {}

    def load(text, radius=0.0, window=0):
        assert mh.compile_text(0, text, params(mh, radius=radius), window, [0.0] * 10) is None

    for name, text, radius, window in (("lines", LINES, 0.0, 0), ("arcs", ARCS, 0.0, 0),
                                       ("square_g42", SQUARE_G42, 2.0, 0), ("chords", circle_chords(), 0.0, 20)):
        items = []
        load(text, radius, window)
        items.append(("run", mh.run(0, 30)))
        items.append(("place", mh.place(0)))
        mh.forget(0)
        items.append(("stopped", mh.run(0, 30, stop_at=0.7)))
        items.append(("place", mh.place(0)))
        items.append(("back", mh.run(0, 32, stop_at=0.3)))
        items.append(("place", mh.place(0)))
        items.append(("back", mh.run(0, 32)))
        items.append(("place", mh.place(0)))
        items.append(("override", mh.run(0, 33, overrides=((0.2, 1.5), (0.6, 0.3)))))
        items.append(("place", mh.place(0)))
        mh.forget(0)
        items.append(("lagging", mh.run(0, 30, feed_every=200)))
        items.append(("place", mh.place(0)))
        mh.forget(0)
        out["harness_" + name] = items
    mh.destroy_all()
    return out


# ------------------------------------------------------------------ record, compare

def record(with_harness):
    lib = library.load()
    traces = {}
    for name, fn in SCENARIOS.items():
        traces[name] = fn(lib)
    lib.ToolChainCore_DestroyCNC(CORE)
    lib.ToolChainCore_TestClock(CORE, KEY, -1.0)
    if with_harness:
        traces.update(harness_traces())
    return traces


def digest(items):
    return hashlib.sha256(pickle.dumps(items, protocol=4)).hexdigest()[:16]


def first_difference(a, b):
    for k, (x, y) in enumerate(zip(a, b)):
        if x != y:
            return k, x, y
    return min(len(a), len(b)), (a[len(b):] or [None])[0], (b[len(a):] or [None])[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--save", type=Path)
    ap.add_argument("--compare", type=Path)
    ap.add_argument("--harness", action="store_true")
    args = ap.parse_args()
    traces = record(args.harness)
    for name, items in traces.items():
        samples = sum(1 for it in items if it and it[0] == "pos")
        print(f"{name:22} {len(items):6} items {samples:6} GetPos samples  {digest(items)}")
    if args.save:
        with gzip.open(args.save, "wb") as fh:
            pickle.dump(traces, fh, protocol=4)
    if args.compare:
        with gzip.open(args.compare, "rb") as fh:
            before = pickle.load(fh)
        bad = 0
        for name in sorted(set(before) | set(traces)):
            if name not in before or name not in traces:
                print(f"{name}: only in {'the record' if name in before else 'this run'}")
                continue
            if before[name] != traces[name]:
                bad += 1
                k, x, y = first_difference(before[name], traces[name])
                print(f"{name}: DIFFERS at item {k}:\n  before {str(x)[:300]}\n  now    {str(y)[:300]}")
        print("identical" if bad == 0 else f"{bad} scenario(s) differ")
        return 1 if bad else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
