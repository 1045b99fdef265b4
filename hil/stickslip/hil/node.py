"""What a session with a stage-model node offers, whatever carries it: the NodeSession protocol
that the serial client (client.NodeClient) and the CAN client (can_client.CanNodeClient) both
satisfy, and the values and errors they share."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Callable, Optional, Protocol, TypeVar

import numpy as np

from .. import _native as N
from ..model import Sawtooth, SimResult
from ..model_file import ModelFile
from ..node_params import node_values
from . import protocol as P

# called with the steps done so far, on long runs (the CLI's progress display)
StepProgress = Optional[Callable[[int], None]]


class HilError(RuntimeError):
    """Every error a node session raises: NodeError (the node refused, with its own reason),
    LinkTimeoutError (no reply in time), LinkClosedError (the connection closed), BadReplyError
    (a reply this client cannot read)."""


class NodeError(HilError):
    """The node refused a request; `name` is the protocol's error name, `reason` the node's own
    words, passed on verbatim."""

    def __init__(self, code: int, request_type: int, reason: str):
        self.code, self.request_type, self.reason = code, request_type, reason
        self.name = P.ERROR_NAMES.get(code, f"error_{code}")
        super().__init__(f"node refused request 0x{request_type:02x}: {self.name}: {reason}")


class LinkTimeoutError(HilError, TimeoutError):
    """No reply in time: the request or its reply was lost."""


class LinkClosedError(HilError, ConnectionError):
    """The node (or the link) closed the connection; what the node said before, verbatim."""


_SOCKET_URL = re.compile(r"socket://([A-Za-z0-9.\-]+|\[[0-9A-Fa-f:]+\]):([0-9]{1,5})(\?.*)?")


def check_socket_url(url: str) -> None:
    """Refuse a malformed socket:// URL by name (pyserial's own message is cryptic); other URLs
    and device paths pass unchanged."""
    if not url.startswith("socket://"):
        return
    m = _SOCKET_URL.fullmatch(url)
    if m is None or not 0 < int(m.group(2)) < 65536:
        raise LinkClosedError(
            f"link URL {url!r}: expected socket://HOST:PORT with a port 1..65535 "
            "(socket://127.0.0.1:5000)"
        )


def model_values(model: ModelFile) -> dict[str, float]:
    """Every node parameter (protocol.PARAM_NAMES) for a model file (node_params.node_values), its
    step included, or HilError for a model the node cannot run (a law it has not: GMS)."""
    try:
        return node_values(model)
    except ValueError as e:
        raise HilError(str(e)) from None


def model_args(model: ModelFile) -> list[str]:
    """stickslip_node's --set options that make it serve `model` (every parameter)."""
    args = []
    for k, v in model_values(model).items():
        args += ["--set", f"{k}={v!r}"]
    return args


def naming_sent_value(e: NodeError, sent: dict) -> NodeError:
    """e, with the value this client sent appended when the node's reason names one of sent's
    fields ("frequency_hz: outside [1e-6, 1e6] Hz (sent 2000000.0)")."""
    field = e.reason.split(":", 1)[0]
    if field not in sent:
        return e
    return NodeError(e.code, e.request_type, f"{e.reason} (sent {sent[field]!r})")


class BadReplyError(HilError):
    """A reply that is too short, of another protocol version, or names a model or variant this
    client does not know: a foreign or newer node, or a corrupted link."""

    def __init__(self, request: str, problem: str):
        self.request, self.problem = request, problem
        super().__init__(f"the node's reply to {request} is not one this client reads: {problem}")


def checked(request: str, payload: bytes, min_len: int) -> bytes:
    """payload, after checking it holds at least min_len bytes."""
    if len(payload) < min_len:
        raise BadReplyError(request, f"{len(payload)} bytes, at least {min_len} expected")
    return payload


@dataclass(frozen=True)
class NodeInfo:
    protocol: int
    model: str
    variant: str
    n_params: int
    dt_s: float
    version: str


@dataclass(frozen=True)
class ParamInfo:
    id: int
    name: str
    value: float
    min: float
    max: float


@dataclass
class Telemetry:
    """Rows of the node's state: SI units, slider position summed in double."""

    step: np.ndarray
    drive_v: np.ndarray
    x_rod_m: np.ndarray
    x_slider_m: np.ndarray
    friction_n: np.ndarray
    # a paced free run's steps that ended after their deadline (the next step's due time), as the
    # serial node reports them; None where the link does not carry them (CAN, lock-step)
    deadline_misses: int | None = None

    @classmethod
    def from_rows(cls, rows: list[tuple]) -> Telemetry:
        a = np.array(rows, dtype=np.float64).reshape(-1, 6)
        hi = np.array([r[3] for r in rows], dtype=np.float32).astype(np.float64)
        lo = np.array([r[4] for r in rows], dtype=np.float32).astype(np.float64)
        return cls(a[:, 0].astype(np.int64), a[:, 1], a[:, 2], hi + lo, a[:, 5])

    @classmethod
    def from_q_result(cls, r: SimResult, rows: slice = slice(1, None)) -> Telemetry:
        """What a fixed-point node (stickslip_node_q, stickslip_fw_q.elf) sends for the q model's
        states r (simulate(..., variant="q")), by the node's rule (docs/protocol.md): each
        integer to float32 (nearest, ties to even), times its power of two; the slider as
        hi = f32(x), lo = f32(x - hi). Exact for |x_slider| < 2^53 LSB, where int -> float64 ->
        float32 rounds once."""

        def ints(v: np.ndarray, signal: str) -> np.ndarray:
            # exact: the values are k 2^-n, and so is their quotient by 2^-n
            return np.round(v[rows] / N.q_scale(signal)).astype(np.int64)

        def f32(q: np.ndarray, signal: str) -> np.ndarray:
            return q.astype(np.float64).astype(np.float32) * np.float32(N.q_scale(signal))

        x = ints(r.x_slider_m, "x_slider_q40")
        hi = x.astype(np.float64).astype(np.float32)
        lo = f32(x - hi.astype(np.int64), "x_slider_q40")
        hi = hi * np.float32(N.q_scale("x_slider_q40"))
        return cls(
            np.round(r.t_s[rows] / r.dt_s).astype(np.int64),
            f32(ints(r.drive_v, "drive_q16"), "drive_q16").astype(np.float64),
            f32(ints(r.x_rod_m, "x_rod_q40"), "x_rod_q40").astype(np.float64),
            hi.astype(np.float64) + lo.astype(np.float64),
            f32(ints(r.force_n, "force_q24"), "force_q24").astype(np.float64),
        )


@dataclass
class LinkStats:
    frames_in: int = 0
    lost_frames: int = 0  # gaps in the node's frame counter
    duplicate_frames: int = 0
    bad_frames: list[str] = field(default_factory=list)


_S = TypeVar("_S", bound="NodeSession")


class NodeSession(Protocol):
    """A session with a node (docs/protocol.md), opened like a python-can bus: a context manager
    that closes the link. `info.variant` is "f32" or "q" (model.VARIANTS)."""

    url: str
    info: NodeInfo
    stats: LinkStats

    def __enter__(self: _S) -> _S: ...

    def __exit__(self, *exc: object) -> None: ...

    def close(self) -> None: ...

    def load_model(self, model: ModelFile) -> None: ...

    def get(self, param: int | str) -> float: ...

    def set(self, param: int | str, value: float) -> float: ...

    def params(self) -> dict[str, ParamInfo]: ...

    def reset(self, drive0_v: float = 0.0, x0_m: float = 0.0) -> None: ...

    def load_waveform(self, w: Sawtooth) -> None: ...

    def lockstep(
        self,
        drive_v: np.ndarray,
        block: int = 40,
        decimation: int = 1,
        progress: StepProgress = None,
    ) -> Telemetry: ...

    def run(
        self,
        steps: int,
        decimation: int = 1,
        paced: int = 0,
        timeout_s: float | None = None,
        progress: StepProgress = None,
    ) -> Telemetry: ...

    def stop(self) -> int: ...
