"""A minimal HMI for the compiler tests: drives the library through ctypes only
(SetGCodeParameters, CompileFromMemory, StatusCNC polling, GetLastError, then a
simulation whose driver callbacks collect every part in order)."""
import ctypes
import math
import time
from dataclasses import dataclass, field

from sf_tch import abi, library
# the example program of the vendor's interpolator manual (section "Example of part of the
# G-code", docs/vendor-sources.md), as printed there: one copy, the conformance suite's
from sf_tch.conformance.dialect import SEED_PROGRAM  # noqa: F401  (the tests import it from here)

INVALID = 1e38                  # the structures description: an absent address's cell holds "> 1e38"
AXES = "XYZCBUVWAO"


@dataclass
class Part:
    kind: str                  # 'G' or 'M'
    func: int
    s: tuple
    e: tuple
    cc: tuple
    pars: dict
    plane: int
    tool: int
    line: int
    file_idx: int
    gindex: int
    per_min: int
    comp: int
    fp: float
    zero: tuple
    ce: tuple                  # the compensated end (m_calcE): the tool centre's path

    @property
    def feed(self):
        return self.pars.get("F")


@dataclass
class Result:
    error: tuple | None        # (number, line, file_idx, text, args)
    parts: list = field(default_factory=list)
    printed: list = field(default_factory=list)

    @property
    def g(self):
        return [p for p in self.parts if p.kind == "G"]

    @property
    def m(self):
        return [p for p in self.parts if p.kind == "M"]


def _wait(lib, core, final, timeout=60.0):
    deadline = time.monotonic() + timeout
    while True:
        status = lib.ToolChainCore_StatusCNC(core)
        if status in final:
            return status
        if time.monotonic() > deadline:
            raise TimeoutError(f"status {status}")
        time.sleep(0.0005)


def default_params(lib, core):
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(p)) == 0
    return p


def last_error(lib, core, refused_call=False):
    """(number, line, file, text, arguments) of the last compilation's or run's error
    (GetLastError), or with refused_call of the last refused call (GetLastCallError)."""
    info = abi.CALLBACK_INFO()
    read = lib.ToolChainCore_GetLastCallError if refused_call else lib.ToolChainCore_GetLastError
    rc = read(core, ctypes.byref(info))
    if rc != 1:
        return None
    return (info.stringId, info.actLine, info.fileIdx, (info.m_fullError or b"").decode(),
            (info.m_errorArguments or b"").decode())


def _part(kind, gm):
    pars = {}
    for i, letter in enumerate("ABCDEFGHIJKLMNOPQRSTUVWXYZ"):
        v = getattr(gm.m_pars, letter)
        if not v > INVALID:         # the host's test as the vendor documents it
            pars[letter] = v
    p10 = lambda s: tuple(getattr(s, a.lower()) for a in AXES)
    return Part(kind, gm.m_func, p10(gm.m_s), p10(gm.m_e), p10(gm.m_cc)[:4], pars,
                ctypes.c_int16(gm.m_planeTool & 0xFFFF).value, gm.m_planeTool >> 16, gm.m_editorLine,
                gm.m_fileIdx, gm.m_gCodeIndex, gm.m_bFeedIsMin & 0xFFFF, gm.m_bFeedIsMin >> 16, gm.m_fp,
                p10(gm.m_zero), p10(gm.m_calcE))


class Host:
    def __init__(self, core, tmp_path):
        self.lib = library.load()
        self.core = core
        self.lib.ToolChainCore_DestroyCNC(core)
        ini = tmp_path / f"core{core}.ini"
        ini.write_text("[Modules]\nCompiler0=x\n[CNC]\nDriver=offline\n")
        assert self.lib.ToolChainCore_LoadFromIni(core, str(ini).encode(), None) == 0
        self.defaults = default_params(self.lib, core)
        # the compiler's tests look at the parts as written: no collinear G1 parts
        # joined (tolerance[2] = 0; the joins: tests/test_join_lines.py)
        self.defaults.tolerance[2] = 0.0
        self._keep = []

    def close(self):
        self.lib.ToolChainCore_DestroyCNC(self.core)

    def params(self, **fields):
        p = abi.GCODE_PARAMETERS.from_buffer_copy(bytes(self.defaults))
        for k, v in fields.items():
            setattr(p, k, v)
        return p

    def compile(self, code, params=None, user=None, prefix=None, postfix=None, name="prog.nc",
                start=None, run=True, **fields):
        lib, core = self.lib, self.core
        p = params if params is not None else self.params(**fields)
        assert lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(p)) == 0
        if user is not None:
            arr = (ctypes.c_double * 100)(*user)
            assert lib.ToolChainCore_SetUserParams(core, arr, 100) == 0
        else:
            assert lib.ToolChainCore_SetUserParams(core, None, 0) == 0
        assert lib.ToolChainCore_GCodePrefixPostfix(
            core, prefix.encode() if prefix else None, postfix.encode() if postfix else None) == 0
        if start is not None:
            coords = (ctypes.c_double * 10)(*start)
            assert lib.ToolChainCore_ResetCNC(core, 0, 10, coords) == 0
        data = code if isinstance(code, bytes) else code.encode()
        assert lib.ToolChainCore_CompileFromMemory(core, name.encode(), data) == 0
        _wait(lib, core, (-1,))
        err = last_error(lib, core)
        res = Result(err)
        if err is not None or not run:
            return res
        return self.run(res)

    def run(self, res=None, keep_position=True):
        """Simulates the compiled program; every part handed to the driver callbacks."""
        lib, core = self.lib, self.core
        res = res or Result(None)
        parts, printed = res.parts, res.printed

        def on_g(user, gm):
            parts.append(_part("G", gm.contents))
            return 0

        def on_m(user, gm):
            parts.append(_part("M", gm.contents))
            return 0

        def on_log(user, tab, text, info):
            if tab & 0xFF == 2:
                printed.append((text or b"").decode())
            return 0

        cbs = [abi.DriverGFunc(on_g), abi.DriverMFunc(on_m), abi.AddOutputLog(on_log)]
        self._keep = cbs
        assert lib.ToolChainCore_SetCallBack(core, abi.CB_DRIVER_G_FUNC, 0, ctypes.cast(cbs[0], ctypes.c_void_p)) == 0
        assert lib.ToolChainCore_SetCallBack(core, abi.CB_DRIVER_M_FUNC, 0, ctypes.cast(cbs[1], ctypes.c_void_p)) == 0
        assert lib.ToolChainCore_SetCallBack(core, abi.CB_ADD_OUTPUT_LOG, 0, ctypes.cast(cbs[2], ctypes.c_void_p)) == 0
        if keep_position:
            assert lib.ToolChainCore_ResetCNC(core, 1, 0, None) == 0
        assert lib.ToolChainCore_StartCNCEx(core, abi.RUN_SIMULATION, None) == 0
        status = _wait(lib, core, (-10, -11, -1, 0, -33, -32))
        for n in (abi.CB_DRIVER_G_FUNC, abi.CB_DRIVER_M_FUNC, abi.CB_ADD_OUTPUT_LOG):
            lib.ToolChainCore_SetCallBack(core, n, 0, None)
        res.status = status
        return res


def close(a, b, tol=1e-9):
    return all(math.isclose(x, y, rel_tol=0, abs_tol=tol) for x, y in zip(a, b))


def ok(host, code, **kw):
    """Compiles (and simulates) code and fails the test on an error."""
    r = host.compile(code, **kw)
    assert r.error is None, r.error
    return r
