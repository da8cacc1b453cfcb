# The compensation strategy of a run: the host's correctionStrategy and tolerances
# (GCODE_PARAMETERS), changed from the program by G172 R C D and reset by G173.
from libc.math cimport sin, M_PI


cdef bint program_add_strategy_region(ProgramBuilder *build, size_t first, bint on, double corner_distance,
                                      double depth, bint drop_arcs) noexcept nogil:
    """Records a G172 (on) / G173 (off) that applies from part `first` on; False =
    no memory. Several before the same part: the last one counts. The compensation
    may be reading the regions beside the compiler: it waits meanwhile."""
    cdef Program *prog = &build.prog
    cdef StrategyRegion *r
    cdef bint ok
    follow_pause(build.follow)
    if prog.n_strategy_regions > 0 and prog.strategy_regions[prog.n_strategy_regions - 1].first == first:
        prog.n_strategy_regions -= 1
    ok = grow(<void **>&prog.strategy_regions, &build.cap_strategy_regions, prog.n_strategy_regions + 1,
               sizeof(StrategyRegion))
    if ok:
        r = &prog.strategy_regions[prog.n_strategy_regions]
        prog.n_strategy_regions += 1
        r.first = first
        r.on = on
        r.corner_distance = corner_distance if corner_distance > 0 else 0.0
        r.depth = depth if depth > 0 else 0.0
        r.drop_arcs = drop_arcs
    follow_resume(build.follow)
    return ok


cdef void comp_config(CompCfg *cfg, const GCODE_PARAMETERS *params) noexcept nogil:
    """The host's strategy."""
    cdef uint32_t depth_bits
    cfg.strategy = params.correctionStrategy
    cfg.mode = 1 if (params.correctionStrategy & CORR_START_MODE_MASK) == 1 else 0
    cfg.tol_angle = (params.tolerance[2] if params.tolerance[2] > 0 else 0.03) * M_PI / 180.0
    cfg.sin_tol = sin(cfg.tol_angle)
    cfg.slack = params.tolerance[1] if params.tolerance[1] > 0 else 0.001
    cfg.min_arc = params.tolerance[4] if params.tolerance[4] > 0 else 0.0
    if params.correctionStrategy & CORR_CORNER_FACTOR_2:
        cfg.factor = 2.0
    else:
        cfg.factor = params.tolerance[5] if params.tolerance[5] > 0 else 3.0
    cfg.corner_distance = 0.0
    depth_bits = (params.correctionStrategy & CORR_SEARCH_DEPTH_MASK) >> 8
    if depth_bits == 1:
        cfg.depth = 10
    elif depth_bits == 2:
        cfg.depth = 50
    elif depth_bits == 3:
        cfg.depth = 100
    elif depth_bits == 4:
        cfg.depth = 500
    elif depth_bits == 5:
        cfg.depth = 1000
    elif depth_bits == 7:
        cfg.depth = (<size_t>-1) / 2     # the whole buffer
    else:
        cfg.depth = 2000


cdef void run_config(const Program *prog, const CompCfg *host, size_t first_part,
                     size_t *region, CompCfg *cfg) noexcept nogil:
    """The strategy of the run starting at `first_part`: the host's, changed by the
    last G172 before it (until a G173). `region` walks the regions in part order."""
    cdef const StrategyRegion *r = NULL
    cfg[0] = host[0]
    while region[0] < prog.n_strategy_regions and prog.strategy_regions[region[0]].first <= first_part:
        region[0] += 1
    if region[0] > 0:
        r = &prog.strategy_regions[region[0] - 1]
    if r == NULL or not r.on:
        return
    if r.corner_distance > 0:
        # R: the intersection of the extended offsets within R of the corner, else an arc
        cfg.strategy |= CORR_CORNER_INTERSECTION
        cfg.corner_distance = r.corner_distance
    if r.depth > 0:
        cfg.depth = <size_t>r.depth
    if r.drop_arcs:
        cfg.strategy |= CORR_DROP_NEGATIVE_ARCS
