# The file table of a core (FileToIdx / IdxToFile): 64 entries, recycled when full,
# whose names live in an append-only store of the core. A host may keep the pointer
# IdxToFile gave and read it while another thread recycles that entry for another
# name: the text it points to is never rewritten. The store holds every distinct name
# once (at most 252 bytes each), so it grows only with names never seen before.
from libc.string cimport strlen, strcmp, memcpy


cdef const char *_name_store_intern(FileTable *t, const char *name) noexcept nogil:
    """The stored copy of `name` (an earlier one, or appended); NULL out of memory.
    Under core.lock."""
    cdef NameChunk *chunk = t.store
    cdef NameChunk *fresh
    cdef size_t at, n = strlen(name) + 1
    while chunk != NULL:
        at = 0
        while at < chunk.used:
            if strcmp(&chunk.text[at], name) == 0:
                return &chunk.text[at]
            at += strlen(&chunk.text[at]) + 1
        chunk = chunk.next
    chunk = t.store
    if chunk == NULL or chunk.used + n > sizeof(chunk.text):
        fresh = <NameChunk *>tc_malloc(sizeof(NameChunk))
        if fresh == NULL:
            return NULL
        fresh.next = chunk
        fresh.used = 0
        t.store = fresh
        chunk = fresh
    memcpy(&chunk.text[chunk.used], name, n)
    chunk.used += n
    return &chunk.text[chunk.used - n]


cdef bint _file_referenced(Core *core, int32_t idx) noexcept nogil:
    """Under core.lock: the loaded program or the compilation that runs uses entry idx."""
    cdef int k
    for k in range(3):
        if core.compile_files[k] == idx:
            return True
        if core.program != NULL and core.program.files[k] == idx:
            return True
    return False


cdef int32_t core_file_to_idx(Core *core, const char *name) noexcept nogil:
    """FileToIdx: the entry of `name`, a new one, or (table full) the least recently
    used entry that no loaded program references, recycled (its run time forgotten);
    -1 when none is free."""
    cdef FileTable *t = &core.files
    cdef int32_t i, found = -1
    cdef const char *stored
    if name == NULL or name[0] == 0 or strlen(name) >= <size_t>TOOL_CHAIN_MAX_FILE_NAME:
        return -1
    if strcmp(name, "__unknown__") == 0: return -1
    if strcmp(name, "__end__") == 0: return -2
    if strcmp(name, "__stop__") == 0: return -3
    if strcmp(name, "__exec__") == 0: return -4
    pthread_mutex_lock(&core.lock)
    for i in range(t.n):
        if strcmp(t.names[i], name) == 0:
            found = i
            break
    if found < 0:
        stored = _name_store_intern(t, name)
        if stored != NULL:
            if t.n < MAX_FILES:
                found = t.n
                t.n += 1
            else:
                for i in range(t.n):
                    if not _file_referenced(core, i) and (found < 0 or t.used[i] < t.used[found]):
                        found = i
        if found >= 0:
            t.names[found] = stored
            t.run_times[found] = -1.0
    if found >= 0:
        t.clock += 1
        t.used[found] = t.clock
    pthread_mutex_unlock(&core.lock)
    return found


cdef const char *core_idx_to_file(Core *core, int32_t idx) noexcept nogil:
    """IdxToFile: the name of an entry, or a special name; never NULL."""
    cdef const char *name = "__unknown__"
    if idx == -2: return "__end__"
    if idx == -3: return "__stop__"
    if idx == -4: return "__exec__"
    pthread_mutex_lock(&core.lock)
    if 0 <= idx < core.files.n:
        name = core.files.names[idx]
    pthread_mutex_unlock(&core.lock)
    return name


cdef double core_file_run_time(Core *core, int32_t idx) noexcept nogil:
    """GetGCodeRunTime: the run time the last simulation measured for entry idx (0 ..
    MAX_FILES - 1); -1 for an entry not in use."""
    cdef double seconds = -1.0
    pthread_mutex_lock(&core.lock)
    if idx < core.files.n:
        seconds = core.files.run_times[idx]
    pthread_mutex_unlock(&core.lock)
    return seconds


cdef bint core_set_file_run_time(Core *core, int32_t idx, double seconds) noexcept nogil:
    """SetGCodeRunTime: the run time of entry idx (0 .. MAX_FILES - 1); False for an
    entry not in use."""
    cdef bint used
    pthread_mutex_lock(&core.lock)
    used = idx < core.files.n
    if used:
        core.files.run_times[idx] = seconds
    pthread_mutex_unlock(&core.lock)
    return used
