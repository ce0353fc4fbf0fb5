"""vbl.render, vbl.merge, vbl.resume. The render runs in a worker thread while the calling thread
waits in Python, so Ctrl-C (SIGINT, delivered to the main thread) arrives at once: while a render
runs on the main thread with Python's default SIGINT handler, a handler of ours takes its place
(so no KeyboardInterrupt interrupts this code half way); it sets the library's cancel flag (vbl_render_options.cancel through libvbl_python), the pass in progress
stops at its next pixel and is dropped, and vbl.RenderInterrupted (a KeyboardInterrupt) is raised
with the film of the complete passes. Without libvbl_python the render stops after the current
pass instead (the pass callback returns "stop")."""

import ctypes
import signal
import threading
import warnings

from . import _native as N
from .errors import ERROR_INTERRUPTED, LimitWarning, RenderInterrupted, argument_error, error_for
from .film import Film

_POLL_SECONDS = 0.05


def _progress_dict(p):
    return {"pass": p.pass_, "passes": p.passes, "elapsed_seconds": p.elapsed_seconds,
            "pass_seconds": p.pass_seconds, "samples_per_pixel": p.samples_per_pixel,
            "first_pass": p.first_pass}


def _should_stop(cancel):
    if cancel is None:
        return False
    if hasattr(cancel, "is_set"):
        return cancel.is_set()
    return bool(cancel())


def _limits(scene, options):
    size = 1024
    while True:
        buf = ctypes.create_string_buffer(size)
        count = N._render_limits(scene.handle, options.handle, buf, size)
        lines = [line for line in buf.value.decode("utf-8", "replace").split("\n") if line]
        if (count <= len(lines) and len(buf.value) + 1 < size) or size >= 1 << 20:
            return lines
        size *= 4  # truncated: ask again with room for every line


def render_limits(scene, **overrides):
    """The documented limits of the methods at the extremes (docs/readme/render.md "Limits at the
    extremes") that render(scene, **overrides) would run into, one message each (a list of str,
    empty for none): the lines `vbl render` prints as warnings (vbl_render_limits). render() and
    resume() issue each as a vbl.LimitWarning (warnings.warn) before rendering."""
    options = scene._render_options()
    options.apply(overrides, "render_limits()")
    return _limits(scene, options)


def _warn_limits(scene, options):
    for line in _limits(scene, options):
        warnings.warn(line, LimitWarning, stacklevel=3)


def render(scene, callback=None, cancel=None, **overrides):
    """Renders `scene` with its `render` block, overridden by keyword arguments named after the
    fields of vbl_render_options (RENDER_OPTION_FIELDS: method, passes, spp, light_paths, seed,
    threads, time_limit, max_bounces, transmittance, mis, vrl_*, vpl_clamp_distance, vbl_*, ...).

    `callback(progress)` runs after every pass (a dict: pass, passes, elapsed_seconds,
    pass_seconds, samples_per_pixel, first_pass); a true return stops the render and the film of
    the passes done is returned (stats["cancelled"] == 1). An exception in the callback stops the
    render and is re-raised. `cancel`: a threading.Event or a callable polled every 50 ms; once
    true the pass in progress stops promptly and is dropped, and the film of the complete passes
    is returned. Ctrl-C does the same and raises vbl.RenderInterrupted (a KeyboardInterrupt) with
    `.film`. A stop before the first pass completes raises vbl.RenderInterrupted with film None.
    A documented limit of the method that the render runs into (render_limits) is issued as a
    vbl.LimitWarning first; the render still runs."""
    options = scene._render_options()
    options.apply(overrides, "render()")
    _warn_limits(scene, options)
    return _run(scene, options, callback, cancel, lambda out: N._render(scene.handle, options.handle, out))


def _run(scene, options, callback, cancel, call):
    flag = ctypes.c_int(0)
    stop = threading.Event()  # fallback without the cancel flag: stop after the current pass
    errors = []

    def trampoline(progress, _user):
        try:
            if callback is not None and callback(_progress_dict(progress.contents)):
                return 1
        except BaseException as error:  # stop the render and re-raise after it returns
            errors.append(error)
            return 1
        return 1 if stop.is_set() else 0

    c_callback = N._PassCallback(trampoline)
    N._options_set_callback(options.handle, c_callback, None)
    if N._native is not None:
        N._native.vbl_py_options_set_cancel(options.handle, ctypes.byref(flag))
    handle = N._P()
    done = {}

    finished = threading.Event()  # not Thread.is_alive(): a join interrupted by Ctrl-C can make a
    # running thread look stopped (CPython 3.11)

    def work():
        try:
            done["code"] = call(ctypes.byref(handle))
            # the library's message is per thread: read it here
            done["error"] = error_for(done["code"]) if done["code"] != 0 else None
        finally:
            finished.set()

    def request_stop():
        flag.value = 1
        stop.set()

    worker = threading.Thread(target=work, name="vbl-render", daemon=True)
    interrupted = []

    def on_sigint(signum, frame):  # in the main thread, between bytecodes: no exception mid-code
        interrupted.append(signum)
        request_stop()

    previous = None
    if threading.current_thread() is threading.main_thread() and \
            signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        if _should_stop(cancel):  # already cancelled: the first pass stops at its first pixel
            request_stop()
        worker.start()
        while not finished.is_set():
            try:
                while not finished.wait(_POLL_SECONDS):
                    if _should_stop(cancel):
                        request_stop()
            except KeyboardInterrupt:  # a handler of the caller's raised it: stop all the same
                interrupted.append(signal.SIGINT)
                request_stop()
    finally:
        while worker.ident is not None and not finished.is_set():  # an exception while waiting
            request_stop()
            try:
                finished.wait()
            except KeyboardInterrupt:
                interrupted.append(signal.SIGINT)
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
        N._options_set_callback(options.handle, N._PassCallback(), None)
        if N._native is not None:
            N._native.vbl_py_options_set_cancel(options.handle, None)
    code = done.get("code")
    film = Film(handle, scene, options, options.get("passes")) if handle else None
    if errors:
        raise errors[0]
    if done.get("error") is not None and code != ERROR_INTERRUPTED:
        raise done["error"]
    if interrupted:
        raise RenderInterrupted("VBL_ERROR_INTERRUPTED", "render interrupted (Ctrl-C); the film holds %s"
                                % ("%d complete passes" % film.stats["passes"] if film else "no pass"), film)
    if code == ERROR_INTERRUPTED and film is None:
        raise done["error"]  # vbl.RenderInterrupted: stopped before a pass completed
    return film


def merge(films):
    """Merges films of disjoint pass ranges of one render (render(..., first_pass=A, passes=B))
    into the film one render of all their passes gives, to float rounding (vbl_film_merge: weighted
    means by passes, summed samples, variance of the mean, Z weighted by passes x alpha, the beauty
    re-summed from the transport layers). The result writes with the first film's scene and options."""
    films = list(films)
    if not films:
        raise argument_error("merge(): no films")
    handles = (N._P * len(films))(*[film.handle for film in films])
    handle = N._P()
    code = N._film_merge(handles, len(films), ctypes.byref(handle))
    if code:
        raise error_for(code)
    first = films[0]
    return Film(handle, first._scene, first._options, sum(f.stats["passes"] for f in films))


def resume(scene, base, callback=None, cancel=None, **overrides):
    """Continues the film `base` (a render of `scene` with fewer passes: a checkpoint) to the
    passes of the scene's `render` block with `overrides` (vbl_render_resume): renders the passes it
    lacks with the single render's seeds and merges, = one render of all passes to float rounding.
    Ctrl-C, `callback` and `cancel` as in render(); limits warned as in render()."""
    options = scene._render_options()
    options.apply(overrides, "resume()")
    _warn_limits(scene, options)
    return _run(scene, options, callback, cancel,
                lambda out: N._render_resume(scene.handle, options.handle, base.handle, out))
