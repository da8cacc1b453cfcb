# Files the host names: the G-code of CompileFromFile and the INI of LoadFromIni.
# Only regular files are read. The open never blocks (O_NONBLOCK: a FIFO without a
# writer, a device that waits for a carrier), so a file that another process
# controls cannot hang the caller; the file type is then taken from the open
# descriptor (fstat), not from the name, so nothing can be swapped in between.
from libc.stdlib cimport malloc, free
from libc.errno cimport errno, EINTR
from posix.fcntl cimport open as posix_open, O_RDONLY, O_NONBLOCK, O_CLOEXEC, O_NOCTTY
from posix.unistd cimport read as posix_read, close as posix_close
from posix.stat cimport struct_stat, fstat, S_ISREG


cdef int file_open_regular(const char *path, size_t *size, int32_t *error) noexcept nogil:
    """A read-only descriptor of the regular file `path` and its size now; -1 with
    *error set (ERR_FILE_OPEN, ERR_NOT_REGULAR_FILE, ERR_FILE_TOO_LARGE)."""
    cdef struct_stat st
    cdef int fd = posix_open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)
    if fd < 0:
        error[0] = ERR_FILE_OPEN
        return -1
    if fstat(fd, &st) != 0:
        posix_close(fd)
        error[0] = ERR_FILE_READ
        return -1
    if not S_ISREG(st.st_mode):
        posix_close(fd)
        error[0] = ERR_NOT_REGULAR_FILE
        return -1
    if st.st_size > MAX_FILE_BYTES:
        posix_close(fd)
        error[0] = ERR_FILE_TOO_LARGE
        return -1
    size[0] = <size_t>st.st_size
    return fd


cdef int32_t file_check_readable(const char *path) noexcept nogil:
    """0 when `path` is a regular file that can be opened for reading, else the
    error number (the same checks as read_whole_file, without reading)."""
    cdef int32_t error = 0
    cdef size_t size
    cdef int fd = file_open_regular(path, &size, &error)
    if fd >= 0:
        posix_close(fd)
    return error


cdef char *read_whole_file(const char *path, size_t *length, int32_t *error) noexcept nogil:
    """The bytes of the regular file `path`, NUL-terminated (malloc'ed); NULL with
    *error set (ERR_FILE_OPEN, ERR_NOT_REGULAR_FILE, ERR_FILE_READ,
    ERR_FILE_TOO_LARGE, ERR_OUT_OF_MEMORY). Reads until the end of the file, which
    may differ from the size fstat told (a file being written, /proc files)."""
    cdef size_t capacity, grown_capacity, used = 0
    cdef ssize_t n
    cdef char *buf
    cdef int fd = file_open_regular(path, &capacity, error)
    if fd < 0:
        return NULL
    capacity += 1                   # room for the terminating NUL, and to see the end
    buf = <char *>malloc(capacity)
    if buf == NULL:
        posix_close(fd)
        error[0] = ERR_OUT_OF_MEMORY
        return NULL
    if capacity >= HUGE_ADVICE_MIN:
        program_advise_huge(buf, capacity)
    while True:
        if used + 1 >= capacity:    # full: the file grew, or fstat said 0
            if used > MAX_FILE_BYTES:
                free(buf)
                posix_close(fd)
                error[0] = ERR_FILE_TOO_LARGE
                return NULL
            # one byte beyond the limit at most: enough to see that a file is too large
            grown_capacity = capacity + FILE_READ_CHUNK
            if grown_capacity > <size_t>MAX_FILE_BYTES + 2:
                grown_capacity = <size_t>MAX_FILE_BYTES + 2
            if not resize(<void **>&buf, grown_capacity, 1):
                free(buf)
                posix_close(fd)
                error[0] = ERR_OUT_OF_MEMORY
                return NULL
            capacity = grown_capacity
        n = posix_read(fd, buf + used, capacity - 1 - used)
        if n > 0:
            used += <size_t>n
        elif n == 0:
            break
        elif errno != EINTR:
            free(buf)
            posix_close(fd)
            error[0] = ERR_FILE_READ
            return NULL
    posix_close(fd)
    buf[used] = 0
    length[0] = used
    return buf
