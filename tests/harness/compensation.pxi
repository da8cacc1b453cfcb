# The compensation alone: compensate_program on parts given from Python, so the
# compensation geometry can be checked without going through the G-code compiler;
# the gouge check's measure of two pieces; the status names and the error texts of the
# catalogue (test_inputs, test_catalogue).

cdef double _compensate_seconds = 0.0


cdef int compensate_program(ProgramBuilder *build, const GCODE_PARAMETERS *params, ErrorInfo *err,
                            output_fn output, warn_fn warn, void *ctx) noexcept nogil:
    """The compensation's whole pass on a complete program in the caller's thread (the
    core feeds it beside the compiler instead, pipeline.pyx): Part.ce, PartExtra.radius
    and the inserted parts of every part with comp 41/42; COMPILE_OK or COMPILE_ERROR
    with err filled. Test-only: the library has no caller for it."""
    cdef CompState S
    cdef size_t more
    compensate_begin(&S, build, params, err, output, warn, ctx)
    compensate_feed(&S, build.prog.n_parts, True, &more)
    return compensate_end(&S, NULL, NULL)


def last_seconds():
    """Wall time of the last compensate_program call."""
    return _compensate_seconds


cdef void _collect(void *ctx, int tab, const char *text) noexcept nogil:
    cdef char *buf = <char *>ctx
    if strlen(buf) + strlen(text) + 2 < 65536:
        strncat(buf, text, 65535)
        strncat(buf, b"\n", 65535)


def compensate(list parts, start, long long strategy=0, corrections=(), tolerances=(), bint strict=False):
    """parts: dicts with kind (1 motion, 2 M), func, e (3..10 values), cc, radius,
    comp (40/41/42), slot, plane, line; strict: GCODE_REZERVA1_COMP_STRICT. Returns
    (parts, error, warnings)."""
    cdef ProgramBuilder build
    cdef Program *prog = &build.prog
    cdef GCODE_PARAMETERS params
    cdef ErrorInfo err
    cdef Part *p
    cdef PartExtra *x
    cdef PartSettings settings
    cdef double end[10]
    cdef int k, rc
    cdef char *warn = <char *>calloc(65536, 1)
    cdef timespec t0, t1
    program_builder_init(&build)
    memset(&params, 0, sizeof(params))
    memset(&err, 0, sizeof(err))
    params.correctionStrategy = <uint32_t>strategy
    if strict:
        params.rezerva1 = <int32_t>GCODE_REZERVA1_COMP_STRICT
    for k, r in enumerate(corrections):
        params.correction[k].size = r
    for k, t in enumerate(tolerances):
        params.tolerance[k] = t
    for k, v in enumerate(start):
        prog.start[k] = v
    memset(&settings, 0, sizeof(settings))
    for idx, d in enumerate(parts):
        p = program_add_part(&build)
        p.kind = d.get("kind", 1)
        p.func = d.get("func", 1)
        e = list(d.get("e", ())) if d.get("e") is not None else []
        part_start(prog, idx, end)         # unset axes stay where the previous part ended
        for k in range(min(len(e), 10)):
            end[k] = e[k]
        program_set_end(&build, p, end)
        for k in range(3):
            p.ce[k] = p.e[k]
        if p.kind == 1 and p.func in (2, 3):
            x = program_part_extra(&build, p)
            cc = d.get("cc", (0, 0, 0))
            for k in range(3):
                x.cc[k] = cc[k] if k < len(cc) else 0.0
            x.radius = d.get("radius", 0.0)
        p.comp = d.get("comp", 40)
        p.comp_slot = d.get("slot", 0 if p.comp == 41 else (1 if p.comp == 42 else 0))
        p.plane = d.get("plane", 17)
        p.line = d.get("line", idx + 1)
        p.gcode_index = 2 * idx
        settings.feed = 1000
        settings.fp = 1.0
        p.settings = <uint32_t>program_settings_index(&build, &settings)
        if p.comp != 40:
            prog.compensated = True
    global _compensate_seconds
    clock_gettime(CLOCK_MONOTONIC, &t0)
    rc = compensate_program(&build, &params, &err, _collect, NULL, warn)
    clock_gettime(CLOCK_MONOTONIC, &t1)
    _compensate_seconds = (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec)
    out = []
    if rc == COMPILE_OK:
        for k in range(<int>prog.n_parts):
            p = &prog.parts[k]
            part_end(prog, p, end)
            out.append(dict(kind=p.kind, func=p.func, line=p.line, gcode_index=p.gcode_index,
                            flags=p.flags, comp=p.comp, plane=p.plane,
                            e=[end[i] for i in range(10)], ce=[p.ce[i] for i in range(3)],
                            cc=[part_extra(prog, p).cc[i] for i in range(3)], radius=part_extra(prog, p).radius,
                            inserted=bool(p.flags & FLAG_INSERTED)))
    error = None
    if rc != COMPILE_OK:
        error = dict(number=err.number, line=err.line, text=err.text.decode("latin-1"))
    warnings = warn[:strlen(warn)].decode("latin-1")
    free(warn)
    program_builder_free(&build)
    return out, error, warnings


def cnc_status_name(int status):
    """The name error texts give a cnc_status (test of the catalogue's table)."""
    return (<bytes>status_name(status)).decode()


def error_text(int number, tuple args):
    """record_error's text and '\n'-separated arguments for error `number` with `args`
    (a str for %s, a number otherwise): test of the catalogue's table."""
    cdef ErrorInfo err
    cdef ErrArg a[16]
    cdef int i
    texts = [arg.encode() if isinstance(arg, str) else None for arg in args[:16]]
    for i in range(len(texts)):
        a[i].text = NULL if texts[i] is None else <const char *>texts[i]
        a[i].num = 0 if texts[i] is not None else args[i]
    record_error(&err, number, -1, 0, 0, a, len(texts))
    return err.text.decode("latin-1"), err.args.decode("latin-1")


cdef bint _piece(XPiece *q, tuple spec):
    """spec: ("line", (sx, sy), (ex, ey)) or ("arc", (sx, sy), (ex, ey), (cx, cy), dir)."""
    cdef double a[2]
    cdef double b[2]
    cdef double c[2]
    memset(q, 0, sizeof(XPiece))
    a[0] = spec[1][0]; a[1] = spec[1][1]
    b[0] = spec[2][0]; b[1] = spec[2][1]
    if spec[0] == "line":
        _cl_line(q, a, b, 0)
        return True
    c[0] = spec[3][0]; c[1] = spec[3][1]
    return _cl_arc(q, a, b, c, distance2d(a[0] - c[0], a[1] - c[1]), spec[4], 0, True)


def piece_gap(tuple t_spec, tuple g_spec, double stop):
    """The gouge check's measure of two pieces (clearance.pyx): (far, gap) with far the
    cheap proof that they are at least `stop` apart and gap the distance where it is
    below `stop` (else a value >= stop)."""
    cdef XPiece t, g
    if not _piece(&t, t_spec) or not _piece(&g, g_spec):
        raise ValueError("no piece")
    return bool(_cl_far(&t, &g, stop)), _cl_piece_gap(&t, &g, stop)


def settings_layout():
    """sizeof(PartSettings) and the bytes of the words _settings_hash reads: the two
    must agree."""
    return sizeof(PartSettings), 4 * SETTINGS_HASH_WORDS
