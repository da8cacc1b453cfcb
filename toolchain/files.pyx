# Files the host names: the G-code of CompileFromFile and the INI of LoadFromIni.
# Only regular files are read. The open never blocks (a FIFO without a writer, a
# device that waits for a carrier, a console), so a file that another process
# controls cannot hang the caller; the file type is then taken from the open file,
# not from the name, so nothing can be swapped in between (platform.h, per system).
from libc.stdlib cimport free


cdef bint file_open_regular(const char *path, size_t max_bytes, tc_file *file, size_t *size,
                            int32_t *error) noexcept nogil:
    """Opens the regular file `path` (UTF-8) for reading and tells its size now; False
    with *error set (ERR_FILE_OPEN, ERR_NOT_REGULAR_FILE, ERR_FILE_READ,
    ERR_FILE_TOO_LARGE beyond max_bytes)."""
    cdef uint64_t bytes_now
    cdef int opened = tc_file_open_regular(path, file, &bytes_now)
    if opened != TC_FILE_OK:
        error[0] = (ERR_FILE_OPEN if opened == TC_FILE_CANNOT_OPEN else
                    ERR_NOT_REGULAR_FILE if opened == TC_FILE_NOT_REGULAR else ERR_FILE_READ)
        return False
    if bytes_now > max_bytes:
        tc_file_close(file[0])
        error[0] = ERR_FILE_TOO_LARGE
        return False
    size[0] = <size_t>bytes_now
    return True


cdef int file_error(ErrorInfo *err, int32_t number, int32_t file_idx, const char *path) noexcept nogil:
    """The error of a file that could not be read, `number` as file_check_readable or
    read_whole_file gave it, naming `path`; -1."""
    if number == ERR_FILE_OPEN:
        return err_file_open(err, file_idx, 0, path)
    if number == ERR_NOT_REGULAR_FILE:
        return err_not_regular_file(err, file_idx, 0, path)
    if number == ERR_FILE_TOO_LARGE:
        return err_file_too_large(err, file_idx, 0, path)
    if number == ERR_OUT_OF_MEMORY:
        return err_out_of_memory(err, file_idx, 0)
    return err_file_read(err, file_idx, 0, path)


cdef int32_t file_check_readable(const char *path) noexcept nogil:
    """0 when `path` is a regular file that can be opened for reading, else the
    error number (the same checks as read_whole_file, without reading)."""
    cdef int32_t error = 0
    cdef size_t size
    cdef tc_file file
    if file_open_regular(path, MAX_FILE_BYTES, &file, &size, &error):
        tc_file_close(file)
    return error


cdef char *read_whole_file(const char *path, size_t max_bytes, size_t *length, int32_t *error) noexcept nogil:
    """The bytes of the regular file `path`, NUL-terminated (malloc'ed); NULL with
    *error set (ERR_FILE_OPEN, ERR_NOT_REGULAR_FILE, ERR_FILE_READ,
    ERR_FILE_TOO_LARGE beyond max_bytes, ERR_OUT_OF_MEMORY). Reads until the end of the file, which
    may differ from the size the open told (a file being written, /proc files)."""
    cdef size_t capacity, grown_capacity, used = 0, piece, ready = 0
    cdef int64_t n
    cdef char *buf
    cdef tc_file file
    if not file_open_regular(path, max_bytes, &file, &capacity, error):
        return NULL
    capacity += 1                   # room for the terminating NUL, and to see the end
    buf = <char *>tc_malloc(capacity)
    if buf == NULL:
        tc_file_close(file)
        error[0] = ERR_OUT_OF_MEMORY
        return NULL
    while True:
        if used + 1 >= capacity:    # full: the file grew, or its size read 0
            if used > max_bytes:
                free(buf)
                tc_file_close(file)
                error[0] = ERR_FILE_TOO_LARGE
                return NULL
            # one byte beyond the limit at most: enough to see that a file is too large
            grown_capacity = capacity + FILE_READ_CHUNK
            if grown_capacity > max_bytes + 2:
                grown_capacity = max_bytes + 2
            if not resize(<void **>&buf, grown_capacity, 1):
                free(buf)
                tc_file_close(file)
                error[0] = ERR_OUT_OF_MEMORY
                return NULL
            capacity = grown_capacity
        # read a chunk at a time into memory readied for it in one call (the copy of
        # one large read would fault every fresh page in on its own)
        piece = capacity - 1 - used
        if piece > READY_CHUNK:
            piece = READY_CHUNK
        ready_ahead(buf, used, &ready, capacity)
        n = tc_file_read(file, buf + used, piece)
        if n > 0:
            used += <size_t>n
        elif n == 0:
            break
        else:
            free(buf)
            tc_file_close(file)
            error[0] = ERR_FILE_READ
            return NULL
    tc_file_close(file)
    buf[used] = 0
    length[0] = used
    return buf
