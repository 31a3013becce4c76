"""The resident checker: with ``OSC2_RESIDENT=1``, ``osc2check`` hands its check to a warm
process instead of importing and loading everything again.

The first command starts the process (in the background; it checks its own files
meanwhile) and later ones hand their checks to it. It has imported the analysis, the
solver and the parser's tables and analysed the standard library once. For each check
it forks a child that takes over the command's standard input, output and error (passed
over a Unix socket), its working folder, its environment and its arguments. The child
checks exactly as the command would: its stored result (:mod:`osc2check.results`), the
findings, the exit status. It sends the status back, and the command exits with it. An
interrupt of the command (SIGINT, SIGTERM, SIGHUP) is passed on to the child.

One process serves one toolkit: the same ``osc2check`` modules, interpreter, module path
(and the folders on it, so an install or upgrade there starts another process) and
``OSC2_*`` variables. It exits after ``OSC2_RESIDENT_IDLE`` seconds without a check
(default 600). Its socket lives in ``$XDG_RUNTIME_DIR`` or in a folder of the user's own
in the temporary folder (mode 0700). A connection from another user is refused. When
no process answers, or the folder is not the user's alone, or the platform cannot pass
descriptors over a Unix socket or fork (Windows), the command checks by itself, as
without the variable.
"""

from __future__ import annotations

import marshal
import os
import signal
import socket
import stat
import sys

from osc2check.fingerprint import digest, toolkit_fingerprint

TYPE_CHECKING = False  # typing's, without importing it (the command's first steps)
if TYPE_CHECKING:
    from collections.abc import Mapping
    from typing import Any

__all__ = ["enabled", "request", "serve"]

ENV = "OSC2_RESIDENT"
IDLE_ENV = "OSC2_RESIDENT_IDLE"
IDLE_SECONDS = 600.0
_FORWARDED = ("SIGINT", "SIGTERM", "SIGHUP")
_NO_STATUS = -(2**31)


def enabled() -> bool:
    """Whether this command should use the resident checker."""
    wanted = os.environ.get(ENV, "").lower() in ("1", "yes", "true", "on")
    return wanted and hasattr(socket, "send_fds") and hasattr(os, "fork")


def _identity() -> dict[str, Any]:
    """What a resident process must share with the command it serves."""
    folders = []  # an install or an upgrade there changes a folder's modification time
    for entry in sys.path:
        try:  # not the working folder ('' or relative): its files come and go
            folders.append(os.stat(entry).st_mtime_ns if os.path.isabs(entry) else 0)
        except OSError:
            folders.append(-1)
    return {
        "toolkit": toolkit_fingerprint(),
        "interpreter": sys.executable,
        "python": sys.version,
        "path": list(sys.path),
        "folders": folders,
        "environment": sorted(
            (k, v) for k, v in os.environ.items() if k.startswith("OSC2") and k != ENV
        ),
    }


def _folder() -> str | None:
    """The folder of the sockets: the user's own, not readable by others; None when
    there is none."""
    runtime = os.environ.get("XDG_RUNTIME_DIR")
    if runtime:
        folder = os.path.join(runtime, "osc2check")
    else:  # the temporary folder as ``tempfile`` finds it on a POSIX system
        temporary = os.environ.get("TMPDIR") or os.environ.get("TMP") or "/tmp"
        folder = os.path.join(temporary, f"osc2check-{os.getuid()}")
    try:
        os.makedirs(folder, mode=0o700, exist_ok=True)
        st = os.stat(folder, follow_symlinks=False)
    except OSError:
        return None
    if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & 0o077:
        return None
    return folder


def _address(identity: Mapping[str, Any]) -> str | None:
    folder = _folder()
    if folder is None:
        return None
    return os.path.join(folder, f"{digest(repr(identity))}.sock")


# ---------------------------------------------------------------------- the command's side


def request(argv: list[str]) -> int | None:
    """Check ``argv`` in the resident process: the exit status, or None when none served
    it (then one is started, and the caller checks by itself; nothing was written)."""
    identity = _identity()
    address = _address(identity)
    if address is None:
        return None
    client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        client.connect(address)
    except OSError:
        client.close()
        _start(identity, address)
        return None
    with client:
        header = marshal.dumps(
            {
                "argv": argv,
                "argv0": sys.argv[0],
                "cwd": os.getcwd(),
                "environment": dict(os.environ),
                "streams": [_stream_settings(s) for s in (sys.stdin, sys.stdout, sys.stderr)],
            }
        )
        try:
            socket.send_fds(client, [len(header).to_bytes(8, "big")], [0, 1, 2])
            client.sendall(header)
            pid = _number(client)
        except OSError:
            return None  # nothing was checked or written: the caller checks by itself
        if pid == _NO_STATUS:
            return None
        forwarded: list[int] = []

        def forward(signum: int, _frame: object) -> None:
            forwarded.append(signum)
            try:
                os.kill(pid, signum)
            except OSError:
                pass

        previous = {}
        for name in _FORWARDED:
            signum = getattr(signal, name, None)
            if signum is not None:
                previous[signum] = signal.signal(signum, forward)
        try:
            status = _number(client)
        except OSError:
            status = _NO_STATUS
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
    if status == _NO_STATUS:
        if forwarded:  # the check ended by the signal: so does the command
            signal.signal(forwarded[-1], signal.SIG_DFL)
            os.kill(os.getpid(), forwarded[-1])
            return 128 + forwarded[-1]
        sys.stderr.write("osc2check: error: the resident checker ended before its check did\n")
        return 2
    return status


def _stream_settings(stream: Any) -> dict[str, str] | None:
    if stream is None:
        return None
    return {
        "encoding": getattr(stream, "encoding", None) or "utf-8",
        "errors": getattr(stream, "errors", None) or "strict",
    }


def _number(conn: socket.socket) -> int:
    data = b""
    while len(data) < 4:
        part = conn.recv(4 - len(data))
        if not part:
            return _NO_STATUS
        data += part
    return int.from_bytes(data, "big", signed=True)


def _start(identity: Mapping[str, Any], address: str) -> None:
    """Start a resident process for ``identity`` in the background (it gives up at once
    when another one already serves the address)."""
    import subprocess

    code = "import sys; from osc2check.resident import serve; serve(sys.argv[1], sys.argv[2])"
    try:
        subprocess.Popen(
            [sys.executable, "-c", code, address, marshal.dumps(identity["path"]).hex()],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
            close_fds=True,
        )
    except OSError:
        pass


# ---------------------------------------------------------------------- the resident side


def serve(address: str, path: str) -> None:
    """Serve checks at ``address`` until idle for ``OSC2_RESIDENT_IDLE`` seconds, with
    ``path`` (marshalled, in hexadecimal) as the module path."""
    import fcntl
    from pathlib import Path

    sys.path[:] = marshal.loads(bytes.fromhex(path))
    where = Path(address)
    lock = open(where.with_suffix(".lock"), "w")  # noqa: SIM115 - held for the whole life
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return  # another process serves this address
    lock.write(f"{os.getpid()}\n")  # whom to stop: kill $(cat the .lock file)
    lock.flush()
    _warm_up()
    import gc

    gc.collect()
    gc.freeze()  # what every check shares: never scanned again by a child's collections
    try:
        idle = float(os.environ.get(IDLE_ENV, IDLE_SECONDS))
    except ValueError:
        idle = IDLE_SECONDS
    where.unlink(missing_ok=True)
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(address)
    os.chmod(address, 0o600)
    server.listen(64)
    server.settimeout(idle)
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # children are reaped by the system
    try:
        while True:
            try:
                conn, _ = server.accept()
            except TimeoutError:
                break
            if not _same_user(conn):
                conn.close()
                continue
            if os.fork() == 0:
                server.close()
                _check_in_child(conn)  # never returns
            conn.close()
    finally:
        server.close()
        where.unlink(missing_ok=True)


def _same_user(conn: socket.socket) -> bool:
    option = getattr(socket, "SO_PEERCRED", None)
    if option is None:
        return True  # the socket's folder is the user's alone
    import struct

    credentials = conn.getsockopt(socket.SOL_SOCKET, option, struct.calcsize("3i"))
    _pid, uid, _gid = struct.unpack("3i", credentials)
    return bool(uid == os.getuid())


def _warm_up() -> None:
    """Import and load what every check needs: a check of a small file, unseen."""
    import contextlib
    import io
    import tempfile
    from pathlib import Path

    from osc2check import cli

    with tempfile.TemporaryDirectory() as folder:
        sample = Path(folder) / "warm_up.osc"
        sample.write_text(
            "import osc.standard\n\nscenario warm_up:\n    car: vehicle\n"
            "    do car.drive(duration: 1s) with:\n        speed(10kph)\n",
            encoding="utf-8",
        )
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            cli.main([str(sample)])


def _check_in_child(conn: socket.socket) -> None:
    """Take over the command's streams, folder, environment and arguments, check, and
    send the exit status."""
    status = _NO_STATUS  # until the command knows the child: it then checks by itself
    try:
        signal.signal(signal.SIGCHLD, signal.SIG_DFL)
        first, fds, _flags, _address = socket.recv_fds(conn, 8, 3)
        size = int.from_bytes(first, "big")
        data = b""
        while len(data) < size:
            part = conn.recv(size - len(data))
            if not part:
                os._exit(1)
            data += part
        request_ = marshal.loads(data)  # from a process of the same user (checked)
        for target, fd in zip((0, 1, 2), fds, strict=True):
            os.dup2(fd, target)
            os.close(fd)
        os.chdir(request_["cwd"])
        os.environ.clear()
        os.environ.update(request_["environment"])
        sys.argv = [request_["argv0"], *request_["argv"]]
        _take_streams(request_["streams"])
        logging = sys.modules.get("logging")
        if logging is not None:  # a handler on the resident process's own stream
            for handler in list(logging.root.handlers):
                logging.root.removeHandler(handler)
        conn.sendall(os.getpid().to_bytes(4, "big", signed=True))
        status = 2  # from now on the command's output is ours
        from osc2check import cache, results

        cache.write_later()  # the command waits for the check, not for the cache

        try:
            status = results.check_interruptible(request_["argv"])
        except SystemExit as exc:  # as the interpreter ends a process with it
            code = exc.code
            status = code if isinstance(code, int) else (0 if code is None else 1)
            if isinstance(code, str):
                sys.stderr.write(code + "\n")
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
    finally:
        try:
            conn.sendall(int(status).to_bytes(4, "big", signed=True))
            conn.close()
        except (OSError, OverflowError):
            pass
        cache_ = sys.modules.get("osc2check.cache")
        if cache_ is not None:
            try:
                cache_.write_kept()  # the command has its answer: now the cache entries
            except Exception:  # noqa: BLE001 - nothing is waiting to be told
                pass
        os._exit(0)


def _take_streams(settings: list[dict[str, str] | None]) -> None:
    """Standard input, output and error on the command's descriptors, with its encodings
    (line-buffered on a terminal, as the interpreter opens them)."""
    modes = ("r", "w", "w")
    streams: list[Any] = []
    for fd, (mode, setting) in enumerate(zip(modes, settings, strict=True)):
        setting = setting or {"encoding": "utf-8", "errors": "strict"}
        stream = open(  # noqa: SIM115 - the process's own streams
            fd,
            mode,
            encoding=setting["encoding"],
            errors=setting["errors"],
            closefd=False,
            buffering=-1 if fd == 0 else 1 if os.isatty(fd) or fd == 2 else -1,
        )
        streams.append(stream)
    sys.stdin, sys.stdout, sys.stderr = streams
