# The connection search: a compiled program (compiler, compensation, G167 arcs,
# planner: the core's pipeline in the caller's thread) placed at a run's start, and
# entry points to every search of toolchain/machine/connect_search.pyx.

cdef void _no_output(void *ctx, int tab, const char *text) noexcept nogil:
    pass


cdef double _seconds(const timespec *t0, const timespec *t1):
    return (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec)


cdef _error(const ErrorInfo *err):
    return (err.number, err.file_idx, err.line, err.text.decode("latin-1"))


cdef _hit(const ConnectHit *hit):
    return dict(part=hit.part, s=hit.s, length=hit.length,
                point=[hit.point[k] for k in range(10)], distance=hit.distance)


cdef class Compiled:
    """A compiled program, its placement (the compile's start until place()), and
    one index (build_index)."""
    cdef ProgramBuilder build
    cdef Placement pl
    cdef ConnectIndex ix
    cdef public double compile_seconds

    def __cinit__(self):
        program_builder_init(&self.build)
        memset(&self.ix, 0, sizeof(ConnectIndex))

    def __dealloc__(self):
        connect_index_free(&self.ix)
        program_builder_free(&self.build)

    @property
    def n_parts(self):
        return self.build.prog.n_parts

    @property
    def main_file_idx(self):
        return self.build.prog.main_file_idx

    def place(self, start):
        """The run starts at `start` (ten axes)."""
        cdef double at[10]
        _fill(at, start, 10)
        placement_init(&self.pl, &self.build.prog, at)

    def parts(self):
        cdef const Part *p
        cdef size_t i
        out = []
        for i in range(self.build.prog.n_parts):
            p = &self.build.prog.parts[i]
            out.append(dict(kind=p.kind, func=p.func, line=p.line, file_idx=part_settings(&self.build.prog, p).file_idx,
                            gcode_index=p.gcode_index, flags=p.flags))
        return out

    def segment(self, size_t i, bint via_record=False):
        """segment_of_placed_part of part i, or (via_record) segment_of_gm of placed_part_to_gm."""
        cdef Segment g
        cdef SIMPLE_GM_PARAMS gm
        if i >= self.build.prog.n_parts:
            raise IndexError(i)
        if via_record:
            placed_part_to_gm(&self.build.prog, i, &self.pl, &gm)
            segment_of_gm(&gm, &g)
        else:
            segment_of_placed_part(&self.build.prog, i, &self.pl, &g)
        out = dict(length=g.length, n_axes=g.n_axes, start=[g.start[k] for k in range(g.n_axes)],
                   end=[g.end[k] for k in range(g.n_axes)], arc=g.arc)
        if g.arc:
            out.update(first=g.first, second=g.second, radius=g.radius,
                       centre=[g.centre[0], g.centre[1]], sweep=g.sweep)
        return out

    def build_index(self, unsigned int axes):
        """(result, error or None, seconds)."""
        cdef ErrorInfo err
        cdef timespec t0, t1
        cdef int rc
        connect_index_free(&self.ix)
        with nogil:
            clock_gettime(CLOCK_MONOTONIC, &t0)
            rc = connect_index_build(&self.ix, &self.build.prog, &self.pl, axes, &err)
            clock_gettime(CLOCK_MONOTONIC, &t1)
        return rc, (None if rc == CONNECT_FOUND else _error(&err)), _seconds(&t0, &t1)

    def index_bytes(self):
        cdef size_t nodes = 2 * self.ix.first_leaf
        return (self.ix.n_items * sizeof(uint32_t) + nodes * 2 * self.ix.n_dims * sizeof(double)
                + nodes * 2 * sizeof(uint32_t))

    def index_dims(self):
        return [self.ix.dims[k] for k in range(self.ix.n_dims)]

    def nearest(self, point, double max_distance=0.0, size_t first=0, size_t end=<size_t>-1):
        """(result, hit, error) of connect_nearest over the index."""
        cdef double q[10]
        cdef ConnectHit hit
        cdef ErrorInfo err
        cdef int rc
        _fill(q, point, 10)
        rc = connect_nearest(&self.ix, q, max_distance, first, end, &hit, &err)
        return _result(rc, &hit, &err)

    def nearest_each(self, point, unsigned int axes, double max_distance=0.0, size_t first=0,
                     size_t end=<size_t>-1, bint hook=False):
        """(result, hit, error) of connect_nearest_each; hook: one that moves every
        part's candidate 1 mm farther, but part 1's to 0."""
        cdef double q[10]
        cdef ConnectHit hit
        cdef ErrorInfo err
        cdef connect_part_fn fn = _test_hook if hook else <connect_part_fn>NULL
        _fill(q, point, 10)
        return _result(connect_nearest_each(&self.build.prog, &self.pl, axes, q, max_distance, first,
                                            end, fn, NULL, &hit, &err),
                       &hit, &err)

    def nearest_seconds(self, points, double max_distance=0.0, size_t first=0, size_t end=<size_t>-1):
        """(wall, CPU) seconds of connect_nearest for each point of `points` (rows of
        ten) in parts [first, end): the wall time includes the thread's preemption,
        the CPU time not."""
        cdef double q[10]
        cdef ConnectHit hit
        cdef timespec w0, w1, c0, c1
        wall, cpu = [], []
        for row in points:
            _fill(q, row, 10)
            with nogil:
                clock_gettime(CLOCK_MONOTONIC, &w0)
                clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0)
                connect_nearest(&self.ix, q, max_distance, first, end, &hit, NULL)
                clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1)
                clock_gettime(CLOCK_MONOTONIC, &w1)
            wall.append(_seconds(&w0, &w1))
            cpu.append(_seconds(&c0, &c1))
        return wall, cpu

    def gindex(self, coords, bint at_end=False):
        cdef double c[16]
        cdef ConnectHit hit
        cdef ErrorInfo err
        _fill(c, coords, 16)
        return _result(connect_gindex(&self.build.prog, &self.pl, c, len(coords), at_end, &hit, &err),
                       &hit, &err)

    def gindex_nearest(self, coords, point, unsigned int axes, double max_distance=0.0):
        cdef double c[16]
        cdef double q[10]
        cdef ConnectHit hit
        cdef ErrorInfo err
        _fill(c, coords, 16)
        _fill(q, point, 10)
        return _result(connect_gindex_nearest(&self.build.prog, &self.pl, c, len(coords), q, axes,
                                              max_distance, &hit, &err), &hit, &err)

    def line(self, coords, bint at_end=False):
        cdef double c[16]
        cdef ConnectHit hit
        cdef ErrorInfo err
        _fill(c, coords, 16)
        return _result(connect_line(&self.build.prog, &self.pl, c, len(coords), at_end, &hit, &err),
                       &hit, &err)

    def mfunc(self, coords, bint relative=False, long long current=-1, int status=-31):
        cdef double c[16]
        cdef ConnectHit hit
        cdef ErrorInfo err
        _fill(c, coords, 16)
        return _result(connect_mfunc(&self.build.prog, &self.pl, c, len(coords), relative, current,
                                     status, &hit, &err), &hit, &err)

    def exact(self, coords, unsigned int axes=0, double tolerance=1e-3):
        cdef double c[16]
        cdef ConnectHit hit
        cdef ErrorInfo err
        _fill(c, coords, 16)
        return _result(connect_exact_point(&self.build.prog, &self.pl, c, len(coords), axes,
                                           tolerance, &hit, &err), &hit, &err)


cdef bint _test_hook(void *ctx, size_t part, double *d2, double *point) noexcept nogil:
    if part == 1:
        d2[0] = 0.0
        point[0] = -1.0
        return True
    d2[0] = (sqrt(d2[0]) + 1.0) ** 2
    return part % 2 == 0            # odd parts: the change is not used


cdef _result(int rc, const ConnectHit *hit, const ErrorInfo *err):
    """(result, hit or None, error or None); CONNECT_OFF_PART gives both."""
    found = rc == CONNECT_FOUND or rc == CONNECT_OFF_PART
    return rc, (_hit(hit) if found else None), (None if rc == CONNECT_FOUND else _error(err))


def bad_argument(name, double value, why):
    """(result, error) of connect_bad_argument."""
    cdef ErrorInfo err
    cdef bytes n = name.encode(), w = why.encode()
    rc = connect_bad_argument(&err, n, value, w)
    return rc, _error(&err)


def compile(text, params=None, start=None, bint cancelled=False):
    """Compiles `text` (str) from `start` (ten axes, default zeros) with
    GCODE_PARAMETERS `params` (bytes, else the defaults): compiler, compensation,
    G167 arcs, planner. Returns a Compiled placed at the compile's start; raises
    ValueError((number, file, line, text)) on a compile error. `cancelled`: an
    ending call came before the compile began (its cancel flag is set)."""
    cdef CompileInput *inp = <CompileInput *>calloc(1, sizeof(CompileInput))
    cdef Compiled c = Compiled()
    cdef ErrorInfo err
    cdef int rc
    cdef bint kept              # (no extent measured before the joins)
    cdef int32_t cancel = 1 if cancelled else 0
    cdef timespec t0, t1
    cdef bytes src = text.encode("latin-1")
    cdef bytes pb
    memset(&err, 0, sizeof(err))
    if params is None:
        default_gcode_parameters(&inp.params)
    else:
        pb = bytes(params)
        if len(pb) != sizeof(GCODE_PARAMETERS):
            free(inp)
            raise ValueError("params: wrong size")
        memcpy(&inp.params, <const char *>pb, sizeof(GCODE_PARAMETERS))
    if start is not None:
        _fill(inp.start, start, 10)
    inp.text = src
    inp.length = len(src)
    inp.file_idx = 0
    inp.prefix_idx = -1
    inp.postfix_idx = -1
    inp.plc = TGM_Data
    inp.cancel = &cancel
    with nogil:
        clock_gettime(CLOCK_MONOTONIC, &t0)
        rc = compile_program(inp, &c.build, &err)
        if rc == COMPILE_OK and c.build.prog.compensated:
            rc = compensate_program(&c.build, &inp.params, &err, _no_output, NULL, NULL)
        if rc == COMPILE_OK:
            rc = insert_arcs(&c.build, &inp.params, &err)
        if rc == COMPILE_OK:
            rc = join_lines(&c.build, &inp.params, False, NULL, NULL, NULL, &kept)
        if rc == COMPILE_OK:
            rc = plan_program(&c.build, &inp.params, 0, 0)
        if rc == COMPILE_OK:
            program_number_parts(&c.build.prog)
        clock_gettime(CLOCK_MONOTONIC, &t1)
    c.compile_seconds = _seconds(&t0, &t1)
    placement_init(&c.pl, &c.build.prog, inp.start)
    free(inp)
    if rc != COMPILE_OK:
        raise ValueError(_error(&err))
    return c
