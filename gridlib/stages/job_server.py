"""A warm process for the stage jobs of a local Snakemake run: each job hands its stage to a
process that has imported gridlib and its libraries once, instead of importing them itself.

A new Python process per stage job imports numpy, xarray, gridlib and what its stage uses
(gstools, pyvista, matplotlib, ...) before it does a fraction of a second of work on a small
case: 0.5-1.3 s of CPU a job, most of the sample workflow's (measured on the project's 2-core VM:
its 89 jobs took 128 s of CPU, a sample case's eight stages 12.4 s for 19,200 cells and 9.7 s
for 784). With the server the sample workflow takes 40 s of CPU instead of 111 s
(docs/stages.md).

For a local run of two or more stage jobs the Snakefile's ``onstart`` starts one *job server*
(:func:`serve_this_run`): a process that imports those modules (:data:`PRELOAD`, the modules of
the run's stages and their :data:`STAGE_LIBRARIES`, the configuration's plugins), listens on a
Unix socket in a private temporary folder, and is named to the jobs by the environment
(:data:`SERVER_ENV`). A stage rule is a ``run:`` job (``stage_job`` in
``workflow/rules/common.smk``), which Snakemake runs in a thread of its own process
(``--force-use-threads``, the default profile): :func:`run_stage_job` sends the server its
:class:`StageJob`, working directory, environment and ``sys.path``, with its standard input,
output and error (file descriptors, ``SCM_RIGHTS``); the server forks a child, a warm copy of
itself, which takes them over and runs the stage (:func:`run_here`: the plugins, then
:func:`~gridlib.stages.common.run_logged` of :func:`~gridlib.stages.pipeline.run_stage`), sends
the exit status and what the child used (:mod:`gridlib.stages.job_usage`) back and ends. No
Python process starts for the job. What Snakemake sees of a job is what a job of its own process
gives: its outputs, its log, its console lines, its exit status, the same files bit for bit; its
benchmark file has the stage's wall time and the child's CPU time, peak memory and bytes read
and written (:class:`JobEnd`; ``stage_job`` in ``workflow/rules/common.smk`` records them).

The job's thread stays in charge: if Snakemake's process ends (a run stopped), the connection
closes and the child kills its own process group (itself and what it started, e.g. OPM Flow).
Each child is forked from the server, which runs no stage itself, so jobs share no state. A job
runs in a new Python process of its own (:func:`run_in_new_process`) where no server is named,
where the server cannot be reached, or where the job's Python is not the server's (a conda or
container job): on other systems than Linux, for a run of a single stage job, with
``--no-hooks``, with ``--software-deployment-method``, or with the configuration's
``job_server: false``. A cluster job of several stages (the SLURM profile's job of a case)
starts a server of its own on its node, at its first stage job (``stage_job``). :func:`run_job`
does the same from a process that runs one job (a script), falling back to that process. The
server ends when the Snakemake process that started it does (it watches a pipe from it).
"""

from __future__ import annotations

import atexit
import contextlib
import gc
import json
import math
import os
import selectors
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass
from importlib import import_module
from pathlib import Path
from typing import Any, NamedTuple

from .job_usage import JobUsage, Meter, usage_of_process

# The environment variables naming the server to the jobs: its socket, and its Python (a job
# run by another interpreter, e.g. a conda environment's, runs in its own process).
SERVER_ENV = "GRIDLIB_JOB_SERVER"
PYTHON_ENV = "GRIDLIB_JOB_SERVER_PYTHON"
# What the server imports before it forks its first child (absent ones are skipped): what every
# job uses, then the modules of the run's stages and what each of them imports only inside its
# functions (a performance hint: a module left out is imported by each job that needs it).
PRELOAD = ("numpy", "xarray", "netCDF4", "gridlib.stages.common", "gridlib.stages.pipeline")
# PIL's image formats beyond PNG, which it imports at its first save (Image.preinit).
_PIL_FORMATS = ("PIL.BmpImagePlugin", "PIL.GifImagePlugin", "PIL.JpegImagePlugin", "PIL.PpmImagePlugin")
STAGE_LIBRARIES: dict[str, tuple[str, ...]] = {
    "horizons": ("scipy.interpolate", "scipy.spatial", "shapely"),
    "grid": ("scipy.interpolate", "shapely"),
    "petrophysics": ("gstools",),
    "coarsen": ("pymetis",),
    "quality": ("matplotlib.pyplot", *_PIL_FORMATS),
    "export": ("pyvista", "pyvista.plotting", "matplotlib.pyplot", "vtkmodules.vtkIOXML"),
    "exchange": ("roffio",),
    # read with a case's trajectory and survey wells (gridlib.config.well_paths), by every stage
    "wells": ("gridlib.io.well_paths", "gridlib.wells.survey"),
    # pyvista imports VTK's interaction and 2-D view modules when a plotter is made (0.15 s)
    "pictures": (
        "pyvista",
        "pyvista.plotting",
        "vtkmodules.vtkInteractionWidgets",
        "vtkmodules.vtkViewsContext2D",
        "matplotlib.pyplot",
        "matplotlib.tri",
        "matplotlib._tri",
        "matplotlib._qhull",
        "mpl_toolkits.axes_grid1.anchored_artists",
        *_PIL_FORMATS,
    ),
    "simulate": ("matplotlib.pyplot",),
}
# What Snakemake sets to a shell or script job's threads (its shell's environment for a job).
JOB_THREAD_VARIABLES = (
    "OMP_NUM_THREADS",
    "GOTO_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
    "NUMEXPR_NUM_THREADS",
)
# Set to 1 in the server's environment unless given (see start_server).
BLAS_THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
# The environment a warm process (the job server, the study workers' fork server) starts with
# where not set: BLAS threads fixed to one when numpy is imported, as Snakemake gives a job of one
# thread (gridlib's own threads follow each job's rule; results do not depend on either); and
# pyvista told that it may plot, since gridlib renders off screen only: otherwise each forked
# job's first plotter asks (an ``xset`` process, then a trial OpenGL context: 0.08 s a job).
WARM_DEFAULTS = dict.fromkeys(BLAS_THREADS, "1") | {"ALLOW_PLOTTING": "true"}
_HEADER = struct.Struct("!I")  # the length of the request that follows the descriptors
# The job's exit status and what its process used: CPU s, peak MiB, MiB read, MiB written (NaN: unknown)
_STATUS = struct.Struct("!i4d")


@dataclass(frozen=True)
class StageJob:
    """One stage job, as a stage rule's script has it: the stage's name, the case file, the
    artifacts' paths (key -> path), the rule's threads and log file, the outputs (whose sizes
    the log gets), the stage's name in the log, its label on the console, and the plugin
    modules that register stages of their own."""

    stage: str
    case: str
    paths: dict[str, str]
    threads: int
    log: str
    outputs: tuple[str, ...] = ()
    name: str | None = None
    label: str | None = None
    plugins: tuple[str, ...] = ()


class JobEnd(NamedTuple):
    """How a stage job ended: its exit status (0: done; 1: failed, the one-line message on
    stderr and the traceback of a bug in the rule's log) and what its process used (None where
    it is not known: the process was killed)."""

    status: int
    usage: JobUsage | None


def run_job(job: StageJob) -> int:
    """Run ``job`` in the run's job server if the environment names one that this Python can
    use and that answers, else in this process; the job's exit status (as :class:`JobEnd`)."""
    end = _run_in_server(job)
    return run_here(job) if end is None else end.status


def job_environment(threads: int, tmpdir: str | None = None) -> dict[str, str]:
    """This process's environment as Snakemake gives it to a shell or script job of ``threads``
    threads and the resource ``tmpdir``: the thread counts of the linear-algebra and OpenMP
    libraries (:data:`JOB_THREAD_VARIABLES`) set to ``threads``, ``TMPDIR`` and ``TMP`` to
    ``tmpdir``."""
    env = dict(os.environ) | dict.fromkeys(JOB_THREAD_VARIABLES, str(threads))
    if tmpdir:
        env |= {"TMPDIR": str(tmpdir), "TMP": str(tmpdir)}
    return env


def run_stage_job(job: StageJob, env: dict[str, str] | None = None) -> JobEnd:
    """Run a stage rule's job from a Snakemake process (a ``run:`` job, which runs in one of its
    threads) with the environment ``env`` (default: this process's; see
    :func:`job_environment`): in the run's job server if the environment names one that
    answers, else in a new Python process (:func:`run_in_new_process`), never in the calling
    process, whose threads run other jobs. How it ended and what its process used."""
    end = _run_in_server(job, env)
    return run_in_new_process(job, env) if end is None else end


def _run_in_server(job: StageJob, env: dict[str, str] | None = None) -> JobEnd | None:
    """How ``job`` ended, run in the job server the environment names, with the environment
    ``env`` (default: this process's); None where none is named, its Python is not this one (a
    conda or container job) or it does not answer (its run ended early)."""
    path = os.environ.get(SERVER_ENV)
    if not path or os.environ.get(PYTHON_ENV) != sys.executable:
        return None
    conn = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        conn.connect(path)
    except OSError:
        conn.close()
        return None
    with conn:
        request = json.dumps(
            {
                "job": asdict(job),
                "cwd": os.getcwd(),
                "env": dict(os.environ if env is None else env),
                "path": sys.path,
            }
        ).encode()
        sys.stdout.flush()
        sys.stderr.flush()
        socket.send_fds(conn, [_HEADER.pack(len(request))], _standard_streams())
        conn.sendall(request)
        answer = _receive(conn, _STATUS.size)
    if answer is None:
        print(
            f"gridlib: {job.label or job.stage}: the job server's process ended without an exit "
            f"status (killed?); see {job.log}",
            file=sys.stderr,
        )
        return JobEnd(1, None)
    status, *figures = _STATUS.unpack(answer)
    cpu, peak, read, written = (None if math.isnan(figure) else figure for figure in figures)
    return JobEnd(status, None if cpu is None else JobUsage(cpu, peak, read, written))


def run_in_new_process(job: StageJob, env: dict[str, str] | None = None) -> JobEnd:
    """Run ``job`` in a new Python process (this interpreter, this gridlib) with the
    environment ``env`` (default: this process's): its standard output and error are this
    process's; it ends when this process does (it watches a pipe from it). How it ended and
    what the process used (its CPU and peak memory, from :func:`os.wait4`)."""
    package_root = str(Path(__file__).resolve().parents[2])
    code = (
        f"import sys; sys.path.insert(0, {package_root!r}); "
        f"from {__name__} import _run_from_parent; sys.exit(_run_from_parent())"
    )
    sys.stdout.flush()
    sys.stderr.flush()
    process = subprocess.Popen(
        [sys.executable, "-c", code, json.dumps(asdict(job))],
        stdin=subprocess.PIPE,
        start_new_session=True,
        env=env,
    )
    try:
        _, wait_status, rusage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(wait_status)
        return JobEnd(process.returncode, usage_of_process(rusage))
    except BaseException:  # the run is stopping: so does the job, and what it started
        with contextlib.suppress(OSError):
            os.killpg(process.pid, signal.SIGKILL)
        raise
    finally:
        if process.stdin is not None:
            process.stdin.close()


def _run_from_parent() -> int:
    """The process of :func:`run_in_new_process`: the job (``sys.argv[1]``, JSON) run here,
    killed with its process group when its parent's pipe (standard input) closes first."""

    def end_with_the_parent() -> None:
        with contextlib.suppress(OSError):
            os.read(0, 1)  # the parent never writes: this returns when its end of the pipe closes
        os.killpg(0, signal.SIGKILL)

    threading.Thread(target=end_with_the_parent, daemon=True).start()
    data = json.loads(sys.argv[1])
    return run_here(StageJob(**data | {key: tuple(data[key]) for key in ("outputs", "plugins")}))


def run_here(job: StageJob, server: bool = False) -> int:
    """Run ``job`` in this process, as a stage rule's script does: its plugins imported, dask
    imported only when used, the stage through :func:`~gridlib.stages.common.run_logged`; the
    exit status. ``server``: this process is a child of the job server, which its log says."""
    from ..io.dask_on_demand import defer_dask_import
    from .common import log, run_logged
    from .pipeline import run_stage

    def stage(*args: Any) -> Any:
        if server:
            log.info("run in the job server: process %d, forked from %d", os.getpid(), os.getppid())
        return run_stage(*args)

    for plugin in job.plugins:
        import_module(plugin)
    defer_dask_import()
    try:
        run_logged(
            job.log,
            stage,
            job.stage,
            job.case,
            job.paths,
            threads=job.threads,
            outputs=list(job.outputs),
            name=job.name or "run_stage",
            label=job.label,
        )
    except SystemExit as exc:  # run_logged's end of a failed stage
        return exc.code if isinstance(exc.code, int) else 1
    return 0


def _standard_streams() -> list[int]:
    """This process's standard input, output and error (``/dev/null`` for a closed one)."""
    fds = []
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
            fds.append(fd)
        except OSError:
            fds.append(os.open(os.devnull, os.O_RDWR))
    return fds


def _receive(conn: socket.socket, size: int) -> bytes | None:
    """Exactly ``size`` bytes from ``conn``; None if it closes first."""
    data = b""
    while len(data) < size:
        chunk = conn.recv(size - len(data))
        if not chunk:
            return None
        data += chunk
    return data


# --- the server -------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class JobServer:
    """A running job server: its socket, its process and the private folder holding the socket."""

    path: str
    process: subprocess.Popen
    folder: str

    def environment(self) -> dict[str, str]:
        """The environment variables that name this server to a job (:func:`run_job`)."""
        return {SERVER_ENV: self.path, PYTHON_ENV: sys.executable}

    def stop(self) -> None:
        """End the server (jobs running in its children finish) and remove its folder."""
        if self.process.stdin is not None and not self.process.stdin.closed:
            self.process.stdin.close()  # the server's signal to end
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        shutil.rmtree(self.folder, ignore_errors=True)


def start_server(
    plugins: Sequence[str] = (), stages: Iterable[str] | None = None, preload: Sequence[str] = PRELOAD
) -> JobServer | None:
    """Start a job server that imports ``preload``, the ``plugins``, the modules of the
    ``stages`` (names of :data:`gridlib.artifacts.STAGES`; None: every stage) and their
    :data:`STAGE_LIBRARIES` before it takes jobs; waits until it has. None if it could not start
    (jobs then run in their own processes), and on other systems than Linux (macOS does not
    let a process that has started some of these libraries fork safely)."""
    if not sys.platform.startswith("linux"):
        return None
    folder = tempfile.mkdtemp(prefix="gridlib-jobs-")  # private (0700): only this user's jobs
    if len(folder) > 90:  # a Unix socket's path has at most 107 bytes: a long TMPDIR will not do
        os.rmdir(folder)
        folder = tempfile.mkdtemp(prefix="gridlib-jobs-", dir="/tmp")
    path = os.path.join(folder, "jobs.sock")
    package_root = str(Path(__file__).resolve().parents[2])  # the gridlib this process uses
    code = f"import sys; sys.path.insert(0, {package_root!r}); from {__name__} import serve; serve()"
    names = None if stages is None else sorted(set(stages))
    settings = json.dumps({"path": path, "plugins": list(plugins), "stages": names, "preload": list(preload)})
    env = WARM_DEFAULTS | os.environ
    process = subprocess.Popen(
        [sys.executable, "-c", code, settings], stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env
    )
    server = JobServer(path, process, folder)
    if process.stdout is None or process.stdout.readline() != b"ready\n":
        server.stop()
        return None
    return server


_serving = threading.Lock()


def serve_this_run(plugins: Sequence[str] = (), stages: Iterable[str] | None = None) -> bool:
    """Start a job server (:func:`start_server`) for the jobs this process (a Snakemake process
    that runs jobs) starts, unless one is named already: named in this process's environment,
    which the jobs inherit, and stopped when this process exits. False if it could not start.
    Threads may call it at once: one server starts."""
    with _serving:
        if os.environ.get(SERVER_ENV):
            return True
        server = start_server(plugins, stages)
        if server is None:
            return False

        def stop() -> None:
            server.stop()
            for name in server.environment():
                os.environ.pop(name, None)

        atexit.register(stop)
        os.environ.update(server.environment())
        return True


def serve() -> None:
    """The server's process (``sys.argv[1]``: its socket's path, plugins and modules to import,
    as JSON): import the modules, listen, fork a child per job, until standard input (a pipe
    from the process that started it) closes."""
    settings = json.loads(sys.argv[1])
    path = settings["path"]
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C stops Snakemake, which then ends this
    _preload(settings["preload"], settings["plugins"], settings["stages"])
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path)
    listener.listen(64)
    selector = selectors.DefaultSelector()
    selector.register(listener, selectors.EVENT_READ)
    selector.register(sys.stdin.fileno(), selectors.EVENT_READ)
    sys.stdout.write("ready\n")
    sys.stdout.flush()
    try:
        while True:
            for key, _ in selector.select(timeout=1.0):
                if key.fileobj is listener:
                    _accept(listener)
                elif not os.read(sys.stdin.fileno(), 1):  # the run's process ended
                    return
            _reap()
    finally:
        listener.close()
        with contextlib.suppress(OSError):
            os.unlink(path)
        _reap(block=True)


def _reap(block: bool = False) -> bool:
    """Collect the ended children (so that their CPU time counts as the server's children's, as
    a job's did as Snakemake's); with ``block``, wait until every child has ended. True if one
    was collected."""
    collected = False
    while True:
        try:
            pid, _ = os.waitpid(-1, 0 if block else os.WNOHANG)
        except ChildProcessError:  # no child left
            return collected
        if pid == 0:  # children left, none ended yet (without block)
            return collected
        collected = True


def preload_modules(stages: Iterable[str] | None = None, preload: Sequence[str] = PRELOAD) -> list[str]:
    """The modules a warm process imports for jobs of ``stages`` (names of
    :data:`gridlib.artifacts.STAGES`; None: every stage): ``preload``, the stages'
    :data:`STAGE_LIBRARIES` and the stages' own modules, in that order, each once."""
    from .. import artifacts

    chosen = [s for s in artifacts.STAGES if stages is None or s.name in set(stages)]
    libraries = [name for stage in chosen for name in STAGE_LIBRARIES.get(stage.name, ())]
    own = [s.function.partition(":")[0] for s in chosen if isinstance(s.function, str)]
    return list(dict.fromkeys([*preload, *libraries, *own]))


def _preload(preload: Sequence[str], plugins: Sequence[str], stages: Sequence[str] | None) -> None:
    """Import what the jobs will use: the plugins, then :func:`preload_modules` (absent ones
    skipped); then :func:`freeze_imports`."""
    from ..io.dask_on_demand import defer_dask_import

    defer_dask_import()
    for name in plugins:
        import_module(name)
    import_present(preload_modules(stages, preload))
    freeze_imports()


def import_present(names: Iterable[str]) -> None:
    """Import the modules ``names`` in order, skipping those not installed (a warm-up: a
    module left out is imported by each job that needs it)."""
    for name in names:
        with contextlib.suppress(ImportError):
            import_module(name)


def freeze_imports() -> None:
    """Move every object the imports made out of the garbage collector's reach (``gc.freeze``),
    in a process that forks workers after its imports: a forked child's full collections then
    scan only what its job makes, not the roughly 360,000 objects of gridlib, xarray, VTK and
    matplotlib's modules (0.04 s of a 5,000-cell variant's pictures), and do not touch (copy)
    the parent's pages. Nothing is lost: module objects live as long as the process anyway."""
    gc.collect()
    gc.freeze()


def _accept(listener: socket.socket) -> None:
    """Take one job from a connecting script and fork its child; a malformed request (not a
    job script's) is dropped."""
    conn, _ = listener.accept()
    try:
        message, fds, _, _ = socket.recv_fds(conn, _HEADER.size, 3)
        if len(message) != _HEADER.size or len(fds) != 3:
            raise ValueError("not a job request")
        data = _receive(conn, _HEADER.unpack(message)[0])
        if data is None:
            raise ValueError("incomplete request")
        request = json.loads(data)
    except (OSError, ValueError):
        conn.close()
        return
    if os.fork() == 0:
        listener.close()
        _child(conn, fds, request)  # never returns
    conn.close()
    for fd in fds:
        os.close(fd)


def _child(conn: socket.socket, fds: list[int], request: dict) -> None:
    """In the forked child: become the job's process (its streams, working directory,
    environment, ``sys.path``), run the stage, send the exit status and what it used, end."""
    code = 1
    meter = Meter()
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        os.setpgid(0, 0)  # a group of its own, killed as a whole if the job's process goes
        for target, fd in enumerate(fds):
            os.dup2(fd, target)
            os.close(fd)
        os.chdir(request["cwd"])
        os.environ.clear()
        os.environ.update(request["env"])
        sys.path[:0] = [p for p in request["path"] if p not in sys.path]
        threading.Thread(target=_end_with_the_job_process, args=(conn,), daemon=True).start()
        job = request["job"] | {key: tuple(request["job"][key]) for key in ("outputs", "plugins")}
        with meter:
            code = run_here(StageJob(**job), server=True)
    except BaseException as exc:  # a child must never return into the server's loop
        print(f"gridlib: job server: {type(exc).__name__}: {exc}", file=sys.stderr)
    finally:
        usage = meter.usage or meter.stop()
        figures = (usage.cpu_seconds, usage.max_rss_mib, usage.read_mib, usage.written_mib)
        with contextlib.suppress(OSError, ValueError):
            sys.stdout.flush()
            sys.stderr.flush()
            conn.sendall(_STATUS.pack(code, *(math.nan if f is None else f for f in figures)))
        os._exit(code)


def _end_with_the_job_process(conn: socket.socket) -> None:
    """Wait for the job's process to close its connection: if that happens before the child
    has sent its status, the job was stopped, so kill the child's process group (the stage
    and what it started)."""
    with contextlib.suppress(OSError):
        conn.recv(1)
    if os.getpgid(0) == os.getpid():  # the child's own group (never the server's or Snakemake's)
        os.killpg(0, signal.SIGKILL)
    os.kill(os.getpid(), signal.SIGKILL)
