# mFuncInsertTable (MfuncInsertType 1): continuous M functions the planner inserts
# where the plan slows down. Our reading of the three entries (the manual names them
# only): 0 before a slow-down: where the speed at the end of a part falls below
# relFeed x its programmed feed, before the part that is `distance` mm or more ahead
# of that point (whole parts); 1 after it: where the speed at the end of a part is
# back at relFeed x its feed or more, after the part `distance` mm or more past that
# point; 2 before G0: before a rapid that follows a cut, `distance` mm ahead likewise.
# Numbers from 1001 on are continuous (never stop the motion), others wait like any
# waiting M function; all carry FLAG_INSERTED. At the program's start "before" means
# after the first part (an insertion follows a part).
from libc.stdlib cimport free, qsort


cdef bint _mfi_add(MfuncInsertions *ins, size_t after, int32_t mfunc) noexcept nogil:
    if not grow(<void **>&ins.items, &ins.cap, ins.n + 1, sizeof(MfuncInsertion)):
        return False
    ins.items[ins.n].after = after
    ins.items[ins.n].mfunc = mfunc
    ins.items[ins.n].seq = ins.n
    ins.n += 1
    return True


cdef size_t _mfi_back(const Program *prog, size_t part, double distance) noexcept nogil:
    """The part after which an M function goes to lie `distance` mm or more before the
    end of `part`, and not after its start: whole parts back."""
    cdef double run = part_length(prog, part)
    cdef size_t k = part
    while run < distance and k > 0:
        k -= 1
        run += part_length(prog, k)
    return k - 1 if k > 0 else 0


cdef size_t _mfi_forward(const Program *prog, size_t part, double distance) noexcept nogil:
    """The part after which an M function goes to come `distance` mm or more after the
    end of `part`."""
    cdef double run = 0.0
    cdef size_t k = part
    while run < distance and k + 1 < prog.n_parts:
        k += 1
        run += part_length(prog, k)
    return k


cdef int _mfi_compare(const void *a, const void *b) noexcept nogil:
    cdef const MfuncInsertion *x = <const MfuncInsertion *>a
    cdef const MfuncInsertion *y = <const MfuncInsertion *>b
    if x.after != y.after:
        return -1 if x.after < y.after else 1
    return -1 if x.seq < y.seq else (1 if x.seq > y.seq else 0)


cdef size_t _mfi_after_of(void *ctx, size_t rec) noexcept nogil:
    return (<MfuncInsertions *>ctx).items[rec].after


cdef void _mfi_make(void *ctx, size_t rec, Part *out, const Part *before, const Part *after) noexcept nogil:
    """A continuous M function at the end of `before` (its position, file and line)."""
    out[0] = before[0]
    out.kind = PART_MFUNC
    out.func = (<MfuncInsertions *>ctx).items[rec].mfunc
    out.flags = FLAG_INSERTED | (FLAG_CONTINUOUS_M if out.func >= 1001 else 0)
    out.gcode_index = before.gcode_index | 1
    out.pars_mask = 0
    out.extra = 0                   # no record: radius and value 0


cdef bint mfunc_insert_wanted(const GCODE_PARAMETERS *params) noexcept nogil:
    cdef int k
    if params.MfuncInsertType != 1:
        return False
    for k in range(3):
        if params.mFuncInsertTable[k].mFunc != 0:
            return True
    return False


cdef int mfunc_insert(ProgramBuilder *build, const GCODE_PARAMETERS *params) noexcept nogil:
    """Inserts the table's M functions where prog.plan slows down; COMPILE_OK, or
    COMPILE_ERROR when out of memory. The caller plans again afterwards."""
    cdef Program *prog = &build.prog
    cdef MfuncInsertions ins
    cdef const INTERNAL_MFUNC_INSERT_TABLE *t = params.mFuncInsertTable
    cdef const Part *p
    cdef size_t k
    cdef double v_prog
    cdef bint slow = False, last_rapid = True, ok = True
    ins.items = NULL
    ins.n = 0
    ins.cap = 0
    for k in range(prog.n_parts):
        p = &prog.parts[k]
        if p.kind != PART_MOTION or prog.plan[k].time <= 0.0:
            continue
        if p.func == 0:
            if not last_rapid and t[MFI_BEFORE_RAPID].mFunc != 0:
                ok = ok and _mfi_add(&ins, _mfi_back(prog, k, t[MFI_BEFORE_RAPID].distance),
                                     t[MFI_BEFORE_RAPID].mFunc)
            last_rapid = True
            continue
        last_rapid = False
        v_prog = part_feed(prog, p, params) / 60.0
        if not slow and prog.plan[k].v_exit < t[MFI_BEFORE_SLOW_DOWN].relFeed * v_prog:
            slow = True
            if t[MFI_BEFORE_SLOW_DOWN].mFunc != 0:
                ok = ok and _mfi_add(&ins, _mfi_back(prog, k, t[MFI_BEFORE_SLOW_DOWN].distance),
                                     t[MFI_BEFORE_SLOW_DOWN].mFunc)
        elif slow and prog.plan[k].v_exit >= t[MFI_AFTER_SLOW_DOWN].relFeed * v_prog:
            slow = False
            if t[MFI_AFTER_SLOW_DOWN].mFunc != 0:
                ok = ok and _mfi_add(&ins, _mfi_forward(prog, k, t[MFI_AFTER_SLOW_DOWN].distance),
                                     t[MFI_AFTER_SLOW_DOWN].mFunc)
    if ok and ins.n > 0:
        qsort(ins.items, ins.n, sizeof(MfuncInsertion), _mfi_compare)
        ok = program_merge(build, ins.n, &ins, _mfi_after_of, _mfi_make, NULL, NULL)
    free(ins.items)
    return COMPILE_OK if ok else COMPILE_ERROR
