"""A restricted, streaming reader of the NumPy object arrays in Poughon et al.'s Marseille skylight
database (docs/import.md): a day file `YYYY-MM-DD_raw.npy` is an NPY header followed by a pickle of
an (N, 4) object array (image, exposure, timestamp, image type), and its annotation file an (N, 2)
one.

Why not `np.load(path, allow_pickle=True)`:
- **Safety.** Unpickling runs whatever callables the file names. This reader's `find_class`
  allows only the few NumPy names such a file holds (`_reconstruct`, `ndarray`, `dtype`,
  `scalar`, and `_codecs.encode` for protocol 2), and each maps to a function here that builds an
  inert proxy and checks its arguments; every other global is refused with the file's name.
  REDUCE calls only those functions, BUILD sets state only on this module's proxies (never an
  attribute of a class), and the opcodes that build other objects (INST, OBJ, NEWOBJ, EXT) are
  refused.
- **Memory.** A day file is ~3 GB of images. The C unpickler keeps every `bytes` object in its memo
  until the end, i.e. the whole file. This reader subclasses the pure-Python `pickle._Unpickler`
  and replaces the opcodes that carry large byte strings: their bytes are skipped (file.seek) or
  copied in chunks straight into a spill file the caller names, and a small `Blob` token stands
  in the memo and in the array. Peak memory is a few MB whatever the file's length. (np.save
  writes protocol 3. Protocol 2 pickles bytes as latin-1 text through _codecs.encode: such a file
  reads, but its images are held in memory.)
"""

from __future__ import annotations

import io
import math
import os
import pickle
import struct
from dataclasses import dataclass
from typing import Any

import numpy as np

# Byte strings at least this long are images: never held in memory (smaller ones are dtype codes,
# scalars' payloads and tiny test images, read as usual).
BIG_BYTES = 1 << 14
_CHUNK = 1 << 22


class MarseilleError(ValueError):
    """Bad input: the message names the file and, where one is known, the row."""

    def __init__(self, file: str, message: str, row: int | None = None):
        self.file, self.row = str(file), row
        super().__init__(f"{file}: " + (f"row {row}: " if row is not None else "") + message)


@dataclass(frozen=True)
class Blob:
    """A large byte string left in the file (pass 1) or copied to `spill` (pass 2)."""
    serial: int          # 0 for the first large byte string of the file, 1 for the next, …
    nbytes: int
    spill: str | None


class _ArrayMarker:
    """What `numpy.ndarray` resolves to: only a tag for _reconstruct."""


_DTYPES = {"b1", "u1", "u2", "u4", "u8", "i1", "i2", "i4", "i8", "f4", "f8", "O4", "O8"}


class DtypeProxy:
    """numpy.dtype(name, align, copy) as pickled, with its byte order from BUILD."""

    def __init__(self, name: Any, align: Any = False, copy: Any = True):
        if not isinstance(name, str) or name not in _DTYPES:
            raise pickle.UnpicklingError(f"dtype {name!r} is not one a day file holds ({', '.join(sorted(_DTYPES))})")
        self.name, self.order = name, "|"

    def __setstate__(self, state: Any) -> None:
        if not (isinstance(state, tuple) and len(state) >= 2 and state[1] in ("<", ">", "|", "=")):
            raise pickle.UnpicklingError(f"dtype {self.name}: unexpected state {state!r:.80}")
        self.order = state[1]

    def resolve(self) -> np.dtype:
        return np.dtype(object) if self.name[0] == "O" else np.dtype(("" if self.order == "|" else self.order) + self.name)


class ArrayProxy:
    """numpy.core.multiarray._reconstruct(ndarray, (0,), b'b') as pickled, then BUILD's state
    (version, shape, dtype, fortran, data). Object arrays keep their list of items; others keep
    their data (bytes for small ones, a Blob for images) to be read by the caller."""

    def __init__(self) -> None:
        self.shape: tuple[int, ...] = (0,)
        self.dtype: np.dtype | None = None
        self.data: Any = None

    def __setstate__(self, state: Any) -> None:
        if not (isinstance(state, tuple) and len(state) == 5):
            raise pickle.UnpicklingError(f"array state of {len(state) if isinstance(state, tuple) else type(state).__name__} items, expected 5")
        _, shape, dt, fortran, data = state
        if not (isinstance(shape, tuple) and len(shape) <= 3 and all(isinstance(s, int) and 0 <= s < 1 << 31 for s in shape)):
            raise pickle.UnpicklingError(f"array shape {shape!r:.80}")
        if not isinstance(dt, DtypeProxy):
            raise pickle.UnpicklingError("array dtype is not a numpy dtype")
        if fortran is not False:
            raise pickle.UnpicklingError("array in Fortran order (a day file's arrays are C order)")
        self.shape, self.dtype = shape, dt.resolve()
        count = math.prod(shape)
        if self.dtype == object:
            if not (isinstance(data, list) and len(data) == count):
                raise pickle.UnpicklingError(f"object array {shape} holds {len(data) if isinstance(data, list) else type(data).__name__} items")
        else:
            nbytes = data.nbytes if isinstance(data, Blob) else len(data) if isinstance(data, (bytes, bytearray)) else -1
            if nbytes != count * self.dtype.itemsize:
                raise pickle.UnpicklingError(f"array {shape} of {self.dtype} has {nbytes} bytes of data, expected {count * self.dtype.itemsize}")
        self.data = data

    def small_array(self) -> np.ndarray:
        """The array itself, for one whose data was read (not a Blob)."""
        if isinstance(self.data, Blob) or self.dtype == object:
            raise TypeError("not a small numeric array")
        return np.frombuffer(bytes(self.data), dtype=self.dtype).reshape(self.shape)


def _reconstruct(cls: Any, shape: Any, typecode: Any) -> ArrayProxy:
    if cls is not _ArrayMarker:
        raise pickle.UnpicklingError("_reconstruct of something other than numpy.ndarray")
    return ArrayProxy()


def _scalar(dt: Any, data: Any = None) -> Any:
    if not isinstance(dt, DtypeProxy) or dt.name[0] == "O":
        raise pickle.UnpicklingError("numpy scalar of a dtype a day file does not hold")
    d = dt.resolve()
    if not isinstance(data, (bytes, bytearray)) or len(data) != d.itemsize:
        raise pickle.UnpicklingError(f"numpy scalar {d} with {len(data) if isinstance(data, (bytes, bytearray)) else 'no'} bytes")
    return np.frombuffer(bytes(data), dtype=d)[0]


def _encode(text: Any, encoding: Any = "latin1") -> bytes:
    """_codecs.encode as protocol 2 uses it for bytes: only latin-1 text."""
    if not isinstance(text, str) or encoding not in ("latin1", "latin-1"):
        raise pickle.UnpicklingError("_codecs.encode other than of text to latin-1")
    return text.encode("latin-1")


_ALLOWED = {}
for _core in ("numpy.core.multiarray", "numpy._core.multiarray"):
    _ALLOWED[(_core, "_reconstruct")] = _reconstruct
    _ALLOWED[(_core, "scalar")] = _scalar
_ALLOWED[("numpy", "ndarray")] = _ArrayMarker
_ALLOWED[("numpy", "dtype")] = DtypeProxy
_ALLOWED[("_codecs", "encode")] = _encode


class RestrictedUnpickler(pickle._Unpickler):  # the pure-Python one: its memo and opcodes are ours to shape
    """Reads a pickle of NumPy arrays, allowing only the globals in _ALLOWED. Large byte strings
    become Blob tokens: skipped, or copied to spill[serial] when the caller names a file for it."""

    def __init__(self, file: io.BufferedReader, spill: dict[int, str] | None = None):
        super().__init__(file)
        self._file = file
        self._spill = spill or {}
        self._size = os.fstat(file.fileno()).st_size
        self.blobs = 0

    def find_class(self, module: str, name: str) -> Any:
        try:
            return _ALLOWED[(module, name)]
        except KeyError:
            raise pickle.UnpicklingError(
                f"global {module}.{name} is not allowed (a day file names only NumPy's array, dtype and scalar "
                "reconstructors): refusing to run it") from None

    def _read_exact(self, n: int) -> bytes:
        data = self.read(n)
        if len(data) != n:
            raise EOFError("pickle data was truncated")
        return data

    def _bytes(self, n: int) -> Any:
        if n < BIG_BYTES:
            return self._read_exact(n)
        serial, self.blobs = self.blobs, self.blobs + 1
        dest = self._spill.get(serial)
        if dest is None and self._unframer.current_frame is None:
            # Outside a frame the bytes follow in the file itself: step over them.
            if self._file.tell() + n > self._size:
                raise EOFError("pickle data was truncated (an image runs past the end of the file)")
            self._file.seek(n, os.SEEK_CUR)
        else:
            out = open(dest, "wb") if dest else None
            try:
                left = n
                while left:
                    chunk = self._read_exact(min(left, _CHUNK))
                    if out:
                        out.write(chunk)
                    left -= len(chunk)
            finally:
                if out:
                    out.close()
        return Blob(serial, n, dest)

    def _load_binbytes(self) -> None:
        (n,) = struct.unpack("<I", self._read_exact(4))
        self.append(self._bytes(n))

    def _load_binbytes8(self) -> None:
        (n,) = struct.unpack("<Q", self._read_exact(8))
        self.append(self._bytes(n))

    def _load_short_binbytes(self) -> None:
        n = self._read_exact(1)[0]
        self.append(self._read_exact(n))

    def _load_reduce(self) -> None:
        args = self.stack.pop()
        func = self.stack[-1]
        if not any(func is f for f in _ALLOWED.values()) or not isinstance(args, tuple):
            raise pickle.UnpicklingError("REDUCE of something other than an allowed NumPy reconstructor")
        self.stack[-1] = func(*args)

    def _load_build(self) -> None:
        state = self.stack.pop()
        inst = self.stack[-1]
        if not isinstance(inst, (ArrayProxy, DtypeProxy)):
            raise pickle.UnpicklingError(f"BUILD of a {type(inst).__name__}: only arrays and dtypes are built")
        inst.__setstate__(state)

    def _refuse(self) -> None:
        raise pickle.UnpicklingError("object-building opcode (INST, OBJ, NEWOBJ, EXT) a NumPy array never uses")

    dispatch = dict(pickle._Unpickler.dispatch)
    dispatch[pickle.REDUCE[0]] = _load_reduce
    dispatch[pickle.BUILD[0]] = _load_build
    for _op in (pickle.INST, pickle.OBJ, pickle.NEWOBJ, pickle.NEWOBJ_EX, pickle.EXT1, pickle.EXT2, pickle.EXT4):
        dispatch[_op[0]] = _refuse
    del _op
    dispatch[pickle.BINBYTES[0]] = _load_binbytes
    dispatch[pickle.BINBYTES8[0]] = _load_binbytes8
    dispatch[pickle.BYTEARRAY8[0]] = _load_binbytes8
    dispatch[pickle.SHORT_BINBYTES[0]] = _load_short_binbytes

    def persistent_load(self, pid: Any) -> Any:
        raise pickle.UnpicklingError("persistent ids are not allowed")


def load_object_array(path: str, spill: dict[int, str] | None = None) -> tuple[ArrayProxy, int]:
    """The object array an NPY file pickles, as an ArrayProxy whose items are Python values, numpy
    scalars and ArrayProxy images (their data a Blob), and the number of images met. Raises
    MarseilleError naming the file for anything else: not NPY, not an object array, a truncated or
    foreign pickle, a refused global."""
    try:
        f = open(path, "rb")
    except OSError as e:
        raise MarseilleError(path, f"cannot open: {e.strerror}") from None
    with f:
        try:
            major, minor = np.lib.format.read_magic(f)
            header = (np.lib.format.read_array_header_1_0(f) if major == 1 else np.lib.format.read_array_header_2_0(f))
        except Exception as e:  # numpy raises ValueError/EOFError for a foreign or cut header
            raise MarseilleError(path, f"not a NumPy .npy file ({e})") from None
        shape, fortran, dtype = header
        if dtype != np.dtype(object):
            raise MarseilleError(path, f"holds a {dtype} array {shape}, expected a pickled object array")
        u = RestrictedUnpickler(f, spill)
        try:
            top = u.load()
        except MarseilleError:
            raise
        except (Exception, RecursionError) as e:
            where = f" (after {u.blobs} image(s))" if u.blobs else ""
            raise MarseilleError(path, f"not a readable day or annotation pickle{where}: "
                                       f"{type(e).__name__}: {e}") from None
        if not (isinstance(top, ArrayProxy) and top.dtype == object and top.shape == shape):
            raise MarseilleError(path, f"the pickle is not the object array {shape} its header announces")
        if f.read(1):
            raise MarseilleError(path, "bytes after the end of the pickle")
        return top, u.blobs
