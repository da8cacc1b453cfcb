"""The axis correction tables ACHS3D??.KOR (docs/axis-correction.md): the binary format
byte for byte, corrections exact at the grid points and multilinear between (against
functions that multilinear interpolation reproduces exactly), the edge value outside,
several tables, every malformed field refused with the file and the field, the tables
kept on a refusal, the INI keys."""
import ctypes
import random
import struct
from ctypes import byref

import numpy as np
import pytest

from sf_tch import abi

ERR_HEADER, ERR_DEFINITION, ERR_SIZE, ERR_VALUE, ERR_TABLES = 730, 731, 732, 733, 734
ERR_TABLE_TOO_LARGE = 25
AXES = "XYZCBUVWAO"


def achs(letters, number, definition, values):
    """The bytes of a table: the letters (corrected axis first) NUL-terminated in a
    128-byte header whose last byte is `number`; (min, max, points) per basis axis;
    the corrections in the file's order (numpy array, the last basis axis fastest)."""
    header = letters.encode() + b"\0"
    header = header.ljust(127, b"\0") + bytes([number])
    block = b"".join(struct.pack("<ffI", lo, hi, n) for lo, hi, n in definition)
    return header + block + np.asarray(values, dtype="<f4").tobytes()


def load(lib, paths, core=0):
    names = (ctypes.c_char_p * max(len(paths), 1))(*[str(p).encode() for p in paths])
    return lib.ToolChainCore_LoadAxisCorrections(core, len(paths), names)


def correct(lib, position, core=0):
    pos = (ctypes.c_double * 10)(*position)
    out = (ctypes.c_double * 10)()
    assert lib.ToolChainCore_CorrectPosition(core, pos, out) == 0
    return list(out)


def at(**axes):
    """Ten coordinates, the named ones set (x=1.5, c=-2)."""
    return [float(axes.get(a.lower(), 0.0)) for a in AXES]


def call_error(lib, core=0):
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastCallError(core, byref(info)) == 1
    return info.stringId, info.m_fullError.decode()


def write(tmp_path, data, name):
    path = tmp_path / name
    path.write_bytes(data)
    return path


def grid(definition):
    return [np.linspace(lo, hi, n) for lo, hi, n in definition]


# ------------------------------------------------------------------ the format, byte for byte

def test_a_table_typed_byte_for_byte(fresh_core, tmp_path):
    """Z over X from 0 to 10 mm in 2 points, corrections 1.0 and 3.0, table number 5,
    written out by hand: little-endian floats and counts."""
    data = (b"ZX\x00" + b"\x00" * 124 + b"\x05"
            + bytes.fromhex("00000000" "00002041" "02000000")      # min 0.0, max 10.0, 2 points
            + bytes.fromhex("0000803f" "00004040"))                # 1.0, 3.0
    assert len(data) == 128 + 12 + 8
    assert load(fresh_core, [write(tmp_path, data, "ACHS3D05.KOR")]) == 0
    for x, dz in ((0, 1.0), (10, 3.0), (5, 2.0), (2.5, 1.5), (-7, 1.0), (1e5, 3.0)):
        assert correct(fresh_core, at(x=x, z=100)) == at(x=x, z=100 + dz)


def test_the_last_basis_axis_varies_fastest(fresh_core, tmp_path):
    """The manual's order: Z11 .. Z1k (k points of Y), then Z21 .. : grid point (i, j)
    holds 10 i + j, and every other axis keeps its coordinate."""
    definition = [(0.0, 20.0, 3), (0.0, 1.0, 2)]
    values = [10 * i + j for i in range(3) for j in range(2)]
    assert load(fresh_core, [write(tmp_path, achs("ZXY", 1, definition, values), "t.kor")]) == 0
    xs, ys = grid(definition)
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            position = at(x=x, y=y, c=7, o=-3)
            expected = list(position)
            expected[2] += 10 * i + j
            assert correct(fresh_core, position) == expected


def test_letters_of_any_case_and_an_axis_corrected_from_itself(fresh_core, tmp_path):
    """A screw's pitch error: X corrected from X."""
    data = achs("xx", 0, [(-10.0, 10.0, 3)], [0.5, 0.0, -0.5])
    assert load(fresh_core, [write(tmp_path, data, "pitch.kor")]) == 0
    assert correct(fresh_core, at(x=-10)) == at(x=-9.5)
    assert correct(fresh_core, at(x=5)) == at(x=4.75)


# ------------------------------------------------------------------ interpolation

def test_z_from_x_and_y_exact_at_the_grid_points_and_linear_between(fresh_core, tmp_path):
    """The bed z = 0.01 x + 0.02 y: at each grid point the file's float; between two
    neighbouring points on a grid line, the straight line between their floats;
    anywhere inside, the plane within the floats' rounding."""
    definition = [(-100.0, 200.0, 31), (0.0, 50.0, 11)]
    xs, ys = grid(definition)
    floats = np.array([[float(np.float32(0.01 * x + 0.02 * y)) for y in ys] for x in xs])   # the file's floats, as doubles
    assert load(fresh_core, [write(tmp_path, achs("ZXY", 3, definition, floats.ravel()), "bed.kor")]) == 0
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            assert correct(fresh_core, at(x=x, y=y))[2] == pytest.approx(float(floats[i, j]), abs=1e-12)
    rng = random.Random(1)
    for _ in range(200):
        i, j, t = rng.randrange(30), rng.randrange(11), rng.random()
        x = xs[i] + t * (xs[i + 1] - xs[i])
        line = (1 - t) * floats[i, j] + t * floats[i + 1, j]
        assert correct(fresh_core, at(x=x, y=ys[j]))[2] == pytest.approx(line, abs=1e-12)
        x, y = rng.uniform(-100, 200), rng.uniform(0, 50)
        assert correct(fresh_core, at(x=x, y=y))[2] == pytest.approx(0.01 * x + 0.02 * y, abs=2e-6)


def _multilinear(x, y, c):
    """A function multilinear interpolation reproduces exactly (no x^2, y^2, c^2);
    its values at integer points are exact floats."""
    return (0.5 + 0.25 * x - 0.125 * y + 0.75 * c + 0.0625 * x * y - 0.25 * x * c
            + 0.03125 * y * c + 0.015625 * x * y * c)


def test_three_basis_axes_reproduce_a_multilinear_function(fresh_core, tmp_path):
    """U from X, Y and C: inside the grid the correction is the function itself (the
    grid's floats are exact), outside it is the function at the nearest point of the
    grid's box."""
    definition = [(-4.0, 4.0, 9), (0.0, 6.0, 4), (-1.0, 1.0, 3)]
    xs, ys, cs = grid(definition)
    values = [_multilinear(x, y, c) for x in xs for y in ys for c in cs]
    assert all(np.float32(v) == v for v in values)
    assert load(fresh_core, [write(tmp_path, achs("UXYC", 7, definition, values), "u.kor")]) == 0
    rng = random.Random(2)
    for _ in range(300):
        x, y, c = rng.uniform(-4, 4), rng.uniform(0, 6), rng.uniform(-1, 1)
        assert correct(fresh_core, at(x=x, y=y, c=c, u=1))[5] == pytest.approx(1 + _multilinear(x, y, c), abs=1e-12)
    for _ in range(300):
        x, y, c = rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-5, 5)
        inside = (min(max(x, -4), 4), min(max(y, 0), 6), min(max(c, -1), 1))
        assert correct(fresh_core, at(x=x, y=y, c=c))[5] == pytest.approx(_multilinear(*inside), abs=1e-12)


def test_tables_read_the_commanded_positions_and_add(fresh_core, tmp_path):
    """X from Z and Z from X do not feed each other; two tables of Z add up."""
    x_from_z = achs("XZ", 1, [(0.0, 10.0, 2)], [0.0, 1.0])
    z_from_x = achs("ZX", 2, [(0.0, 10.0, 2)], [0.0, 2.0])
    z_from_y = achs("ZY", 3, [(0.0, 10.0, 2)], [0.0, 4.0])
    paths = [write(tmp_path, d, f"t{k}.kor") for k, d in enumerate((x_from_z, z_from_x, z_from_y))]
    assert load(fresh_core, paths) == 0
    assert correct(fresh_core, at(x=5, y=5, z=5)) == pytest.approx(at(x=5.5, y=5, z=5 + 1 + 2))
    assert correct(fresh_core, at(x=10, y=0, z=0)) == pytest.approx(at(x=10, y=0, z=2))


def test_correct_position_arguments(fresh_core):
    lib = fresh_core
    pos = (ctypes.c_double * 10)(*range(10))
    assert lib.ToolChainCore_CorrectPosition(0, pos, pos) == 0 and list(pos) == list(range(10))   # no tables: a copy
    assert lib.ToolChainCore_CorrectPosition(0, None, pos) == -1
    assert lib.ToolChainCore_CorrectPosition(0, pos, None) == -1
    pos[9] = float("nan")
    assert lib.ToolChainCore_CorrectPosition(0, pos, (ctypes.c_double * 10)()) == -1
    assert lib.ToolChainCore_CorrectPosition(3, pos, pos) == abi.TOOL_CHAIN_BAD_INTR_INDEX
    assert lib.ToolChainCore_LoadAxisCorrections(0, 1, None) == -1
    assert lib.ToolChainCore_LoadAxisCorrections(3, 0, None) == abi.TOOL_CHAIN_BAD_INTR_INDEX


# ------------------------------------------------------------------ bad files

GOOD = ("ZXY", 4, [(0.0, 10.0, 3), (-5.0, 5.0, 2)], [0, 1, 2, 3, 4, 5])


def _with(index, value):
    """GOOD's bytes with the 4 bytes at `index` replaced by value (float or int)."""
    data = bytearray(achs(*GOOD))
    data[index:index + 4] = struct.pack("<f" if isinstance(value, float) else "<I", value)
    return bytes(data)


BAD = [
    ("short-header", achs(*GOOD)[:100], ERR_HEADER, "header: the file has 100 bytes, the header alone 128"),
    ("not-a-letter", achs("ZQ", 1, [(0.0, 1.0, 2)], [0, 0]), ERR_HEADER, "byte 1 (0x51) is no axis letter"),
    ("digit-letter", achs("Z1", 1, [(0.0, 1.0, 2)], [0, 0]), ERR_HEADER, "byte 1 (0x31) is no axis letter"),
    ("five-letters", achs("ZXYCB", 1, [(0.0, 1.0, 2)] * 4, [0] * 16), ERR_HEADER, "more than four axis letters"),
    ("no-basis", achs("Z", 1, [], []), ERR_HEADER, "no basis axis"),
    ("no-letters", achs("", 1, [], []), ERR_HEADER, "no basis axis"),
    ("basis-twice", achs("ZXX", 1, [(0.0, 1.0, 2)] * 2, [0] * 4), ERR_HEADER, "basis axis X is named twice"),
    ("no-definition", achs(*GOOD)[:128 + 20], ERR_SIZE, "has 148 bytes; its header and definition block ask for 152"),
    ("min-nan", _with(128, float("nan")), ERR_DEFINITION, "definition of basis axis X: min = nan is not a finite number"),
    ("max-inf", _with(132 + 12, float("inf")), ERR_DEFINITION, "basis axis Y: max = inf is not a finite number"),
    ("min-too-far", _with(128, -2e6), ERR_DEFINITION, "min = -2e+06 is outside <-1e6, 1e6> mm"),
    ("min-not-below-max", _with(128, 10.0), ERR_DEFINITION, "min = 10 is not below max = 10"),
    ("one-point", _with(136 + 12, 1), ERR_DEFINITION, "basis axis Y: 1 grid points: at least 2"),
    ("no-points", _with(136, 0), ERR_DEFINITION, "basis axis X: 0 grid points"),
    ("value-missing", achs(*GOOD)[:-4], ERR_SIZE, "has 172 bytes; its header and definition block ask for 176"),
    ("value-left-over", achs(*GOOD) + b"\0\0\0\0", ERR_SIZE, "has 180 bytes"),
    ("huge-grid", _with(136, 0xFFFFFFFF), ERR_SIZE, "ask for"),
    # 2^21 x 2^21 x 2^24 points: 2^66, a product that wraps to 0 in 64 bits
    ("grid-wraps", achs("ZXYC", 1, [(0.0, 100.0, 1 << 21), (0.0, 100.0, 1 << 21), (0.0, 100.0, 1 << 24)], []),
     ERR_SIZE, "has 164 bytes; its header and definition block ask for 295147905179352825856"),
    ("value-nan", _with(152 + 4 * 5, float("nan")), ERR_VALUE, "grid point 5: the correction = nan is not a finite number"),
    ("value-too-large", _with(152, 1e7), ERR_VALUE, "grid point 0: the correction = 1e+07 is outside"),
]


@pytest.mark.parametrize("data, number, reason", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_a_bad_file_is_refused_naming_the_file_and_the_field(fresh_core, tmp_path, data, number, reason):
    good = write(tmp_path, achs("YX", 9, [(0.0, 1.0, 2)], [0.0, 0.5]), "good.kor")
    assert load(fresh_core, [good]) == 0
    bad = write(tmp_path, data, "ACHS3DXX.KOR")
    assert load(fresh_core, [good, bad]) == -1
    got_number, text = call_error(fresh_core)
    assert got_number == number and f"'{bad}'" in text and reason in text, text
    assert correct(fresh_core, at(x=1)) == at(x=1, y=0.5)          # the tables stay


def test_the_set_of_tables(fresh_core, tmp_path):
    paths = [write(tmp_path, achs("ZX", k, [(0.0, 1.0, 2)], [0, k]), f"t{k}.kor") for k in range(9)]
    assert load(fresh_core, paths[:8]) == 0
    assert correct(fresh_core, at(x=1))[2] == sum(range(8))
    assert load(fresh_core, paths) == -1
    assert call_error(fresh_core) == (ERR_TABLES, f"Axis correction table '{paths[8]}': 9 tables: at most 8 per core")
    again = write(tmp_path, achs("YX", 3, [(0.0, 1.0, 2)], [0, 1]), "again.kor")
    assert load(fresh_core, [paths[3], again]) == -1
    number, text = call_error(fresh_core)
    assert number == ERR_TABLES and f"'{again}': its number 3 is the number of '{paths[3]}' too" in text
    assert correct(fresh_core, at(x=1))[2] == sum(range(8))
    for name in (tmp_path / "missing.kor", tmp_path):
        assert load(fresh_core, [paths[0], name]) == -1
        assert call_error(fresh_core)[0] in (1, 13)
    names = (ctypes.c_char_p * 2)(str(paths[0]).encode(), None)
    assert fresh_core.ToolChainCore_LoadAxisCorrections(0, 2, names) == -1
    assert load(fresh_core, []) == 0
    assert correct(fresh_core, at(x=1)) == at(x=1)


def test_random_bytes_never_crash(fresh_core, tmp_path):
    """Truncated, extended and overwritten tables: read, or refused with 730..733."""
    rng = random.Random(4)
    base = achs(*GOOD)
    for case in range(300):
        data = bytearray(base)
        for _ in range(rng.randint(1, 4)):
            what = rng.random()
            if what < 0.5:
                at_byte = rng.randrange(len(data))
                data[at_byte] = rng.randrange(256)
            elif what < 0.75:
                del data[rng.randrange(len(data)):]
            else:
                data += bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        rc = load(fresh_core, [write(tmp_path, bytes(data), f"m{case}.kor")])
        assert rc == 0 or call_error(fresh_core)[0] in (ERR_HEADER, ERR_DEFINITION, ERR_SIZE, ERR_VALUE)
        correct(fresh_core, at(x=rng.uniform(-50, 50), y=rng.uniform(-50, 50), c=3))


# ------------------------------------------------------------------ INI

def test_the_ini_names_the_tables(fresh_core, tmp_path):
    write(tmp_path, achs("ZX", 1, [(0.0, 10.0, 2)], [0.0, 1.0]), "ACHS3D01.KOR")
    write(tmp_path, achs("ZY", 2, [(0.0, 10.0, 2)], [0.0, 2.0]), "ACHS3D02.KOR")
    ini = tmp_path / "m.ini"
    ini.write_text("[Corrections]\nAxisTable1=ACHS3D01.KOR\nAxisTable3 = ACHS3D02.KOR\n")
    assert fresh_core.ToolChainCore_LoadFromIni(2, str(ini).encode(), None) == 0
    assert correct(fresh_core, at(x=10, y=5), core=2)[2] == 2.0
    ini.write_text("[GCodeParameters]\ncorrection0=0.5\n[Corrections]\nAxisTable1=ACHS3D01.KOR\nAxisTable2=none.KOR\n")
    assert fresh_core.ToolChainCore_LoadFromIni(2, str(ini).encode(), None) == abi.TOOL_CHAIN_XEXEC
    assert "none.KOR" in call_error(fresh_core, 2)[1]
    assert correct(fresh_core, at(x=10, y=5), core=2)[2] == 2.0
    params = abi.GCODE_PARAMETERS()
    fresh_core.ToolChainCore_GetGCodeParameters(2, byref(params))
    assert params.correction[0].size == 0.0
    ini.write_text("[Corrections]\nAxisTable2=ACHS3D02.KOR\n")
    assert fresh_core.ToolChainCore_LoadFromIni(2, str(ini).encode(), None) == 0
    assert correct(fresh_core, at(x=10, y=5), core=2)[2] == 1.0         # the named ones only


def test_reloading_while_another_thread_corrects(fresh_core, tmp_path):
    """A reload never pulls a table from under a caller applying it: each correction is
    one table's or the other's, whole."""
    import threading
    one = write(tmp_path, achs("ZXY", 1, [(0.0, 10.0, 50), (0.0, 10.0, 50)], [1.0] * 2500), "one.kor")
    two = write(tmp_path, achs("ZX", 2, [(0.0, 10.0, 3)], [2.0, 2.0, 2.0]), "two.kor")
    assert load(fresh_core, [one]) == 0
    seen, done = set(), threading.Event()

    def reload():
        for k in range(300):
            assert load(fresh_core, [two if k % 2 else one]) == 0
        done.set()

    thread = threading.Thread(target=reload)
    thread.start()
    while not done.is_set():
        seen.add(correct(fresh_core, at(x=3, y=4))[2])
    thread.join()
    assert seen <= {1.0, 2.0}


def test_a_table_file_beyond_64_mib_is_refused_before_it_is_read(fresh_core, tmp_path):
    good = write(tmp_path, achs("YX", 9, [(0.0, 1.0, 2)], [0.0, 0.5]), "good.kor")
    assert load(fresh_core, [good]) == 0
    big = tmp_path / "ACHS3D02.KOR"
    with open(big, "wb") as f:                  # sparse: no 64 MiB written
        f.truncate((64 << 20) + 1)
    assert load(fresh_core, [good, big]) == -1
    assert call_error(fresh_core) == (ERR_TABLE_TOO_LARGE, f"Table file '{big}' is larger than 64 MiB")
    assert correct(fresh_core, at(x=1)) == at(x=1, y=0.5)
