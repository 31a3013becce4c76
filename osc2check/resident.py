"""The resident checker: with ``OSC2_RESIDENT=1``, ``osc2check`` hands its check to a warm
process instead of importing and loading everything again.

The first command starts the process (in the background; it checks by itself
meanwhile) and later ones hand their checks to it. The process has imported the
analysis, the solver and the parser's tables and analysed the standard library once,
with no file and no configuration of anyone's. For each check it forks a child that
takes over the command's standard input, output and error (passed over a Unix socket),
its working folder, environment, arguments and ignored signals. The child checks
exactly as the command would: its stored result (:mod:`osc2check.results`), the
findings, the exit handlers, the exit status. It sends the status back, and the
command exits with it. Signals to the command are passed on to the child (SIGINT,
SIGTERM, SIGHUP, SIGQUIT), and a command that ends otherwise (SIGKILL) ends its check;
a stop (Ctrl-Z) stops the command alone. The child writes the start-up cache's new
entries after the command has its answer, its streams let go.

One process serves one toolkit and one set of process settings: the same ``osc2check``
files (with the grammar and standard library), interpreter, module path (and the
folders on it, so an install or upgrade there starts another process), ``OSC2_*`` and
``PYTHON*`` variables, file mode mask and resource limits. It exits after
``OSC2_RESIDENT_IDLE`` seconds without a check (default 600), or on SIGTERM
(:func:`stop`); its process id is in the ``.lock`` file beside its socket. The socket
lives in ``$XDG_RUNTIME_DIR`` or in a folder of the user's own in the temporary folder
(mode 0700); a connection from another user is refused. When no process answers in
time, the folder is not the user's alone, the socket's path is too long, a standard
stream is closed, or the platform cannot pass descriptors over a Unix socket or fork
(Windows), the command checks by itself, as without the variable; nothing has been
written by then.
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

__all__ = ["answering", "enabled", "request", "serve", "stop"]

ENV = "OSC2_RESIDENT"
IDLE_ENV = "OSC2_RESIDENT_IDLE"
IDLE_SECONDS = 600.0
#: how long a command waits for the resident process to take its check (its warm-up
#: included, when the command arrived while it started)
TAKE_SECONDS = 60.0
_MAX_ADDRESS = 100  # bytes of a socket's path (the system's limit is about 108)
_FORWARDED = ("SIGINT", "SIGTERM", "SIGHUP", "SIGQUIT")
_NO_STATUS = -(2**31)
_GO = b"\x01"


def enabled() -> bool:
    """Whether this command should use the resident checker."""
    wanted = os.environ.get(ENV, "").lower() in ("1", "yes", "true", "on")
    return wanted and hasattr(socket, "send_fds") and hasattr(os, "fork")


def _identity() -> dict[str, Any]:
    """What a resident process must share with the command it serves."""
    import resource

    folders = []  # an install or an upgrade there changes a folder's modification time
    for entry in sys.path:
        try:  # not the working folder ('' or relative): its files come and go
            folders.append(os.stat(entry).st_mtime_ns if os.path.isabs(entry) else 0)
        except OSError:
            folders.append(-1)
    mask = os.umask(0)
    os.umask(mask)
    limits = sorted(
        (name, resource.getrlimit(getattr(resource, name)))
        for name in dir(resource)
        if name.startswith("RLIMIT_")
    )
    return {
        "toolkit": toolkit_fingerprint(),
        "interpreter": sys.executable,
        "python": sys.version,
        "path": list(sys.path),
        "folders": folders,
        "environment": sorted(
            (k, v)
            for k, v in os.environ.items()
            if (k.startswith("OSC2") and k != ENV) or k.startswith("PYTHON")
        ),
        "umask": mask,
        "limits": limits,
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
    address = os.path.join(folder, f"{digest(repr(identity))}.sock")
    return address if len(os.fsencode(address)) <= _MAX_ADDRESS else None


def answering(folder: str, wait: float = 0.0) -> bool:
    """Whether a resident process answers at a socket in ``folder`` (its sockets' folder,
    ``$XDG_RUNTIME_DIR/osc2check``), asking again for up to ``wait`` seconds: for a
    script that starts one and waits for it."""
    import glob
    import time

    deadline = time.monotonic() + wait
    while True:
        for path in glob.glob(os.path.join(glob.escape(folder), "*.sock")):
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
                try:
                    probe.connect(path)
                    return True
                except OSError:
                    pass
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.2)


def stop(folder: str) -> int:
    """Stop the resident processes whose sockets are in ``folder`` (SIGTERM to the process
    id in each lock a process still holds: never a stale id); how many."""
    import fcntl
    import glob

    stopped = 0
    for path in glob.glob(os.path.join(glob.escape(folder), "*.lock")):
        try:
            with open(path) as lock:
                try:
                    fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    continue  # nobody holds it: its process has left
                except OSError:
                    pid = int(lock.read() or "0")
            if pid > 0:
                os.kill(pid, signal.SIGTERM)
                stopped += 1
        except (OSError, ValueError):
            pass
    return stopped


# ---------------------------------------------------------------------- the command's side


def request(argv: list[str]) -> int | None:
    """Check ``argv`` in the resident process: the exit status, or None when none took
    it (then one is started when none runs, and the caller checks by itself: nothing
    was written)."""
    for fd in (0, 1, 2):  # a closed one would be taken by the socket
        try:
            os.fstat(fd)
        except OSError:
            return None
    try:
        identity = _identity()
        address = _address(identity)
    except OSError:  # a file of the toolkit that cannot be looked at: check here
        return None
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
        forwarded = [int(getattr(signal, name)) for name in _FORWARDED if hasattr(signal, name)]
        ignored = [s for s in forwarded if signal.getsignal(s) == signal.SIG_IGN]
        header = marshal.dumps(
            {
                "argv": argv,
                "argv0": sys.argv[0],
                "cwd": os.getcwd(),
                "environment": dict(os.environ),
                "streams": [_stream_settings(s) for s in (sys.stdin, sys.stdout, sys.stderr)],
                "ignored": ignored,
            }
        )
        try:
            client.settimeout(TAKE_SECONDS)
            socket.send_fds(client, [len(header).to_bytes(8, "big")], [0, 1, 2])
            client.sendall(header)
            pid = _number(client)
        except OSError:  # a timeout too: closing the socket tells the child to give up
            return None
        if pid == _NO_STATUS:
            return None
        received: list[int] = []
        previous = _pass_signals(pid, [s for s in forwarded if s not in ignored], received)
        try:
            client.settimeout(None)
            client.sendall(_GO)  # from now on the child writes the command's output
            status = _number(client)
        except OSError:
            status = _NO_STATUS
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
    if status == _NO_STATUS:
        if received:  # the check ended by the signal: so does the command
            signal.signal(received[-1], signal.SIG_DFL)
            os.kill(os.getpid(), received[-1])
            return 128 + received[-1]
        sys.stderr.write("osc2check: error: the resident checker ended before its check did\n")
        return 2
    return status


def _pass_signals(pid: int, signums: list[int], received: list[int]) -> dict[int, Any]:
    """Pass ``signums`` on to the child ``pid``; the handlers they replace, by signal.

    A stop (Ctrl-Z) is not passed on: a child stopped with a command that is then
    killed would stay stopped, holding the command's streams open."""

    def forward(signum: int, _frame: object) -> None:
        received.append(signum)
        _kill(pid, signum)

    return {s: signal.signal(s, forward) for s in signums}


def _kill(pid: int, signum: int) -> None:
    try:
        os.kill(pid, signum)
    except OSError:
        pass


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
            cwd="/",
        )
    except OSError:
        pass


# ---------------------------------------------------------------------- the resident side


def serve(address: str, path: str) -> None:
    """Serve checks at ``address`` until idle for ``OSC2_RESIDENT_IDLE`` seconds, with
    ``path`` (marshalled, in hexadecimal) as the module path."""
    import fcntl
    import math

    sys.path[:] = marshal.loads(bytes.fromhex(path))
    os.chdir("/")
    lock_path = address.removesuffix(".sock") + ".lock"
    lock = open(lock_path, "a+")  # noqa: SIM115 - held for the whole life
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return  # another process serves this address
    lock.seek(0)
    lock.truncate()
    lock.write(f"{os.getpid()}\n")  # whom to stop (resident.stop), while the lock is held
    lock.flush()
    try:
        idle = float(os.environ.get(IDLE_ENV, IDLE_SECONDS))
    except ValueError:
        idle = IDLE_SECONDS
    if not (math.isfinite(idle) and idle > 0):
        idle = IDLE_SECONDS
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    # stopped (resident.stop): its socket and lock are cleared as when it leaves idle
    signal.signal(signal.SIGTERM, lambda _signum, _frame: sys.exit(0))
    try:
        if os.path.exists(address):
            os.unlink(address)
        server.bind(address)
        os.chmod(address, 0o600)
        server.listen(64)  # commands that come during the warm-up wait for it
        _warm_up()
        import gc

        gc.collect()
        gc.freeze()  # what every check shares: never scanned again by a child's collections
        server.settimeout(idle)
        signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # children are reaped by the system
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
                _check_in_child(conn, lock.fileno())  # never returns
            conn.close()
    except OSError:
        pass  # the socket cannot be made: the commands check by themselves
    finally:
        lock.seek(0)
        lock.truncate()  # no process id left to kill by mistake
        server.close()
        try:  # the address is ours while the lock is
            os.unlink(address)
        except OSError:
            pass
        lock.close()


def _same_user(conn: socket.socket) -> bool:
    option = getattr(socket, "SO_PEERCRED", None)
    if option is None:
        return True  # the socket's folder is the user's alone
    import struct

    credentials = conn.getsockopt(socket.SOL_SOCKET, option, struct.calcsize("3i"))
    _pid, uid, _gid = struct.unpack("3i", credentials)
    return bool(uid == os.getuid())


_SAMPLE = """\
import osc.standard

scenario warm_up:
    car: vehicle
    do car.drive(duration: 1s) with:
        speed(10kph)
"""


def _warm_up() -> None:
    """Import and load what every check needs, from a text of its own: no file is read
    and no configuration is looked for (one found above a folder could name plug-ins)."""
    from osc2check import analysis, cli, output  # noqa: F401 - imported to be warm

    analysis.analyze([analysis.SourceInput("<warm-up>", _SAMPLE)])


def _check_in_child(conn: socket.socket, lock: int) -> None:
    """Take over the command's streams, folder, environment and arguments, check when
    the command says go, and send the exit status."""
    os.close(lock)  # a lock held by a child would outlive the resident process
    status = _NO_STATUS  # until the command knows the child: it then checks by itself
    answered = False
    try:
        signal.signal(signal.SIGCHLD, signal.SIG_DFL)
        conn.settimeout(TAKE_SECONDS)
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
        _take_process(request_)
        conn.sendall(os.getpid().to_bytes(4, "big", signed=True))
        conn.settimeout(None)
        if conn.recv(1) != _GO:  # the command gave up waiting: it checks by itself
            os._exit(0)
        status = 2  # from now on the command's output is ours
        try:
            _end_with_the_command(conn, lambda: answered)
            status = _check(request_["argv"])
        except KeyboardInterrupt:  # before the check began
            sys.stderr.write("osc2check: interrupted\n")
            sys.stderr.flush()
            status = 130
    finally:
        answered = True
        try:
            conn.sendall(int(status).to_bytes(4, "big", signed=True))
            conn.close()
        except (OSError, OverflowError):
            pass
        _let_go_of_the_streams()  # whoever reads the command's output sees its end now
        cache_ = sys.modules.get("osc2check.cache")
        if cache_ is not None:
            try:
                cache_.write_kept()  # the command has its answer: now the cache entries
            except Exception:  # noqa: BLE001 - nothing is waiting to be told
                pass
        os._exit(0)


def _let_go_of_the_streams() -> None:
    """Standard input, output and error on the null device: the command's are closed
    here, so a pipe that reads its output ends with the command, not with this child."""
    try:
        null = os.open(os.devnull, os.O_RDWR)
        for fd in (0, 1, 2):
            os.dup2(null, fd)
        os.close(null)
    except OSError:
        pass


def _take_process(request_: dict[str, Any]) -> None:
    """The command's folder, environment, arguments, streams and ignored signals; none of
    the resident process's exit handlers, log handlers or temporary folder."""
    import atexit

    os.chdir(request_["cwd"])
    os.environ.clear()
    os.environ.update(request_["environment"])
    sys.argv = [request_["argv0"], *request_["argv"]]
    _take_streams(request_["streams"])
    for name in _FORWARDED:
        signum = getattr(signal, name, None)
        if signum is not None:
            ignored = signum in request_["ignored"]
            default = signal.default_int_handler if name == "SIGINT" else signal.SIG_DFL
            signal.signal(signum, signal.SIG_IGN if ignored else default)
    atexit._clear()  # the check's own exit handlers run at its end, as in its own process
    logging = sys.modules.get("logging")
    if logging is not None:  # a handler on the resident process's own stream
        for handler in list(logging.root.handlers):
            logging.root.removeHandler(handler)
    tempfile = sys.modules.get("tempfile")
    if tempfile is not None:
        setattr(tempfile, "tempdir", None)  # noqa: B010 - found again from the environment


def _end_with_the_command(conn: socket.socket, answered: Any) -> None:
    """End this child when the command ends before its answer (killed): nothing would
    read what it writes."""
    import threading

    def watch() -> None:
        try:
            conn.recv(1)
        except OSError:
            pass
        if not answered():
            os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


def _check(argv: list[str]) -> int:
    """The check, ended as the interpreter ends the command's own process (its exit
    handlers, an uncaught exception's traceback and status 1)."""
    import atexit

    from osc2check import cache, results
    from osc2check.gc_pause import off_for_the_command

    cache.write_later()  # the command waits for the check, not for the cache
    off_for_the_command()
    try:
        status = results.check_interruptible(argv)
    except SystemExit as exc:
        code = exc.code
        status = code if isinstance(code, int) else (0 if code is None else 1)
        if isinstance(code, str):
            sys.stderr.write(code + "\n")
    except BaseException:  # noqa: BLE001 - as the interpreter reports it
        import traceback

        traceback.print_exc()
        status = 1
    results.ignore_interrupts()  # the check has its answer
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    return status


def _take_streams(settings: list[dict[str, str] | None]) -> None:
    """Standard input, output and error on the command's descriptors, with its encodings
    (line-buffered on a terminal, unbuffered with ``-u``, as the interpreter opens them)."""
    modes = ("r", "w", "w")
    streams: list[Any] = []
    # the resident process's own output stream says how the interpreter opened it (-u)
    unbuffered = bool(getattr(sys.__stdout__, "write_through", False))
    for fd, (mode, setting) in enumerate(zip(modes, settings, strict=True)):
        setting = setting or {"encoding": "utf-8", "errors": "strict"}
        stream = open(  # noqa: SIM115 - the process's own streams
            fd,
            mode,
            encoding=setting["encoding"],
            errors=setting["errors"],
            closefd=False,
            newline="\n",  # as the interpreter opens them on POSIX: no translation
            buffering=-1 if fd == 0 else 1 if os.isatty(fd) or fd == 2 else -1,
        )
        if fd and unbuffered:
            stream.reconfigure(write_through=True)  # type: ignore[attr-defined]
        streams.append(stream)
    sys.stdin, sys.stdout, sys.stderr = streams
