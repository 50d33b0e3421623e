#!/usr/bin/python3
"""A Modbus/TCP lab controller for dry runs and tests of hybridtest's modbus transfer.

Written with pymodbus (Debian: python3-pymodbus), a Modbus stack independent of the libmodbus
client it talks to. It plays an actuator controller with the default register profile of
docs/modbus.md: an ideal or first-order-lagged actuator pushing a linear specimen.

  holding 0-1  command position (float32, mm)   holding 2  command sequence (uint16)
  input   0-1  measured position (float32, mm)  input   2-3  measured force (float32, N)
  input   4    acknowledged sequence (uint16)   input   5  status (bit 0 enabled, 1 fault,
  input   6-7  lab time, uint32 ms (--lab-time)            bit 2 holding)
  coil    0    enable                           coil    1  hold

Several actuators (--actuators N): each has the block above (float32, or float64 with --type
float64: command 0-3, sequence 4, position 0-3, force 4-7, ack 8, status 9), repeated at a
stride (--stride-holding, --stride-input, --stride-coils; default packed: 3, 6 and 2 registers
for float32, 0 coils shares one enable and one hold) or from given bases (--holding-base 0,100
--input-base 0,50 --coil-base 0,10); the lab time lies after the last input block unless
--lab-time-address says where. The specimen couples them: force_i = sum_j K_ij (x_j - p0_j)
with --stiffness-matrix "K11,K12;K21,K22" in N/mm (actuator coordinates), p0 per actuator
(--p0-mm 20,30). Every command republishes every actuator's position and force, and only the
commanded actuator's ack.

A command is taken when the sequence register changes. The controller moves (instantly, or
with the lag until within --settle-mm), samples the force k (x - p0), and then publishes
position, force and the ack (after --ack-delay-ms of wall time, to exercise polling). It
refuses a command (Modbus exception 4) while not enabled, while holding, or beyond the stroke.

Usage (by hand, for a dry run; Ctrl-C stops it):
  python3 tests/transfer/modbus_server.py --listen 127.0.0.1:5020 --stiffness 5.25
  hybridtest run examples/rotor/modbus.yaml --bench 127.0.0.1:5020 --out results/modbus.csv

Test faults (N counts an actuator's commands from 1; KIND@N/A for actuator A, default 1): --fault silent@N (never acks command N and later),
fault@N (sets the fault bit instead of acking N), exception@N (answers the write of N with
Modbus exception 4), mute@N (stops answering anything from command N on), holding@N (acks N
but reports holding from then on, as a controller that holds on its own), disabled@N (acks N
but clears the enabled bit), offset@N (from N on, the measured position is --offset-mm off the
position the actuator reached: a following error or a position sensor fault), stale@N (from N
on, the controller acknowledges each command before it updates its data: the ack comes with the
position and force of the previous command).

--log-commands FILE appends one line "SEQUENCE COMMAND_MM" (with " ACTUATOR" when there are
several) for every command received (before it is checked), so a test can assert the largest step between consecutive commands. A
restarted controller (--start-mm MM) comes up where the actuator is.

Prints "modbus_server: listening on HOST:PORT (...)" once it accepts connections.
"""
import argparse
import asyncio
import logging
import math
import os
import struct
import sys
import time

def pymodbus_advice(error):
    """Why pymodbus could not be imported by this interpreter, and the fix."""
    here = f"{sys.executable} (Python {sys.version.split()[0]})"
    debian = "/usr/lib/python3/dist-packages/pymodbus"
    try:
        import pymodbus  # noqa: F401  (present, but not the API this script needs)
        return (f"the pymodbus {getattr(pymodbus, '__version__', '?')} that {here} imports "
                f"from {pymodbus.__file__} lacks what this script needs ({error}); run it with "
                f"Debian's /usr/bin/python3 and python3-pymodbus 3.0")
    except ImportError:
        pass
    if os.path.isdir(debian) and os.path.dirname(debian) not in sys.path:
        return (f"python3-pymodbus is installed ({debian}) but {here} does not see Debian's "
                f"packages ({os.path.dirname(debian)} is not on its sys.path); run the script "
                f"with Debian's interpreter, as its first line says: /usr/bin/python3 "
                f"{sys.argv[0]}")
    return (f"pymodbus is missing for {here} ({error}); install python3-pymodbus "
            f"(scripts/install-deps.sh) and run the script with /usr/bin/python3")


try:
    from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                    ModbusSlaveContext)
    from pymodbus.server.async_io import ModbusTcpServer
except ImportError as error:  # pragma: no cover
    print(f"modbus_server: {pymodbus_advice(error)}", file=sys.stderr)
    sys.exit(3)

ENABLED, FAULT, HOLDING = 1, 2, 4  # status bits
KINDS = ("silent", "fault", "exception", "mute", "holding", "disabled", "offset", "stale")


def numbers(text, n, what):
    """A comma-separated list of n numbers (one value: every actuator)."""
    values = [float(v) for v in str(text).split(",")]
    if len(values) == 1:
        values *= n
    if len(values) != n:
        raise SystemExit(f"modbus_server: {what}: {len(values)} values for {n} actuators")
    return values


class Layout:
    """Where actuator k's block lies: the default profile's fields (widths w = 2 for float32,
    4 for float64) from its holding, input and coil base address."""

    def __init__(self, args):
        n, self.fmt = args.actuators, "d" if args.type == "float64" else "f"
        w = self.w = 4 if args.type == "float64" else 2
        def bases(given, stride, what):
            if given:
                return [int(v) for v in numbers(given, n, what)]
            return [k * stride for k in range(n)]
        self.holding = bases(args.holding_base, args.stride_holding or w + 1, "--holding-base")
        self.input = bases(args.input_base, args.stride_input or 2 * w + 2, "--input-base")
        coils = args.stride_coils if args.stride_coils is not None else 2
        self.coil = bases(args.coil_base, coils, "--coil-base")
        self.lab = args.lab_time_address if args.lab_time_address is not None else \
            max(self.input) + 2 * w + 2

    def cmd(self, k): return self.holding[k]
    def seq(self, k): return self.holding[k] + self.w
    def pos(self, k): return self.input[k]
    def ack(self, k): return self.input[k] + 2 * self.w
    def status(self, k): return self.input[k] + 2 * self.w + 1
    def enable(self, k): return self.coil[k]
    def hold(self, k): return self.coil[k] + 1


class Controller(ModbusSlaveContext):
    """The register space plus the actuators and the specimen behind them."""

    def __init__(self, args):
        self.n = n = args.actuators
        self.at = at = Layout(args)
        size = max(max(at.holding), max(at.input), max(at.coil), at.lab) + 16
        super().__init__(co=ModbusSequentialDataBlock(0, [False] * size),
                         di=ModbusSequentialDataBlock(0, [False] * 16),
                         hr=ModbusSequentialDataBlock(0, [0] * size),
                         ir=ModbusSequentialDataBlock(0, [0] * size), zero_mode=True)
        self.args = args
        if args.stiffness_matrix:   # [N/mm], rows separated by ';'
            self.k = [[float(v) for v in row.split(",")] for row in args.stiffness_matrix.split(";")]
            if len(self.k) != n or any(len(row) != n for row in self.k):
                raise SystemExit(f"modbus_server: --stiffness-matrix: expected {n} x {n}")
        else:
            self.k = [[args.stiffness if i == j else 0.0 for j in range(n)] for i in range(n)]
        self.p0 = numbers(args.p0_mm, n, "--p0-mm")
        self.faults = [dict() for _ in range(n)]   # per actuator: kind -> command number
        for spec in args.fault:
            kind, _, at_ = spec.partition("@")
            number, _, actuator = at_.partition("/")
            if kind not in KINDS or not number.isdigit() or \
                    not (actuator == "" or actuator.isdigit() and 1 <= int(actuator) <= n):
                raise SystemExit(f"modbus_server: --fault {spec}: expected KIND@N or KIND@N/A "
                                 f"(actuator A, 1..{n}) with KIND one of {', '.join(KINDS)}")
            self.faults[int(actuator or 1) - 1][kind] = int(number)
        start = args.start_mm if args.start_mm is not None else args.p0_mm
        self.position = numbers(start, n, "--start-mm")   # [mm]
        self.lab_time = 0.0          # [s]
        self.commands = [0] * n
        self.last_sequence = [0] * n
        self.acks = [0] * n
        self.status = [0] * n
        self.forced_holding = [False] * n   # holding@N: reports holding whatever the coil says
        self.forced_disabled = [False] * n  # disabled@N: reports not enabled whatever the coil
        self.offset_mm = [0.0] * n          # offset@N: measured minus actual position [mm]
        self.log = open(args.log_commands, "a", encoding="utf-8") if args.log_commands else None
        self.publish()

    # -- encoding ----------------------------------------------------------------------------
    def words(self, fmt, value):
        raw = struct.pack(">" + fmt, value)
        w = [int.from_bytes(raw[i:i + 2], "big") for i in range(0, len(raw), 2)]
        return w[::-1] if self.args.word_order == "low_first" else w

    def value(self, fmt, words):
        w = words[::-1] if self.args.word_order == "low_first" else words
        return struct.unpack(">" + fmt, b"".join(x.to_bytes(2, "big") for x in w))[0]

    def set_input(self, address, words):
        super().setValues(4, address, words)

    def publish(self, k=None, ack=None):
        """Every actuator's position and force (the specimen couples them); actuator k's ack."""
        if k is not None:
            self.acks[k] = ack
        at, fmt = self.at, self.at.fmt
        for i in range(self.n):
            force = sum(self.k[i][j] * (self.position[j] - self.p0[j]) for j in range(self.n))
            measured = self.position[i] + self.offset_mm[i]
            self.set_input(at.pos(i), self.words(fmt, measured) + self.words(fmt, force) +
                           [self.acks[i]])
        if self.args.lab_time:
            self.set_input(at.lab, self.words("I", int(round(self.lab_time * 1e3)) % 2**32))
        self.set_status()

    def set_status(self):
        for i in range(self.n):
            enable = super().getValues(1, self.at.enable(i), 1)[0]
            hold = super().getValues(1, self.at.hold(i), 1)[0]
            enabled = enable and not self.forced_disabled[i]
            holding = hold or self.forced_holding[i]
            self.status[i] = (self.status[i] & FAULT) | (ENABLED if enabled else 0) | \
                (HOLDING if holding else 0)
            self.set_input(self.at.status(i), [self.status[i]])

    # -- the actuator -------------------------------------------------------------------------
    def move(self, k, target):
        """Moves actuator k to `target` [mm]; returns the settled position, adds its lab time."""
        a = self.args
        self.lab_time += a.overhead_ms * 1e-3
        if a.actuator == "ideal":
            return target
        gap = self.position[k] - target
        tau = a.time_constant_ms * 1e-3
        steps = 0 if abs(gap) <= a.settle_mm else math.ceil(
            tau * math.log(abs(gap) / a.settle_mm) / 1e-3)
        self.lab_time += steps * 1e-3
        return target + gap * math.exp(-steps * 1e-3 / tau)

    def command(self, k, target, sequence):
        self.commands[k] += 1
        n, faults = self.commands[k], self.faults[k]
        if self.log:
            self.log.write(f"{sequence} {target!r}" + (f" {k + 1}" if self.n > 1 else "") + "\n")
            self.log.flush()
        if faults.get("mute", 0) and n >= faults["mute"]:
            while True:          # stop answering: the client's response timeout must fire
                time.sleep(3600)
        if faults.get("exception", 0) == n:
            raise RuntimeError(f"command {n} refused (test fault)")
        if not self.status[k] & ENABLED or self.status[k] & HOLDING:
            raise RuntimeError("command refused: not enabled, or holding")
        if not math.isfinite(target) or abs(target) > self.args.stroke_mm:
            raise RuntimeError(f"command {target} mm refused: beyond the stroke")
        if faults.get("silent", 0) and n >= faults["silent"]:
            return
        if faults.get("fault", 0) == n:
            self.status[k] |= FAULT
            self.set_input(self.at.status(k), [self.status[k]])
            return
        if faults.get("stale", 0) and n >= faults["stale"]:
            self.publish(k, sequence)                 # the ack, with the previous data ...
            self.position[k] = self.move(k, target)   # ... updated after it: read with the next
            return
        self.position[k] = self.move(k, target)
        self.forced_holding[k] |= faults.get("holding", 0) == n
        self.forced_disabled[k] |= faults.get("disabled", 0) == n
        if faults.get("offset", 0) and n >= faults["offset"]:
            self.offset_mm[k] = self.args.offset_mm
        if self.args.ack_delay_ms > 0:
            asyncio.get_event_loop().call_later(self.args.ack_delay_ms * 1e-3, self.publish,
                                                k, sequence)
        else:
            self.publish(k, sequence)

    # -- the Modbus side ----------------------------------------------------------------------
    def setValues(self, fc_as_hex, address, values):
        table = self.decode(fc_as_hex)
        if table == "h":
            end = address + len(values)
            def after(first, count):   # the holding registers as this write leaves them
                regs = super(Controller, self).getValues(3, first, count)
                for i in range(count):
                    if address <= first + i < end:
                        regs[i] = values[first + i - address]
                return regs
            for k in range(self.n):
                if not address <= self.at.seq(k) < end:
                    continue
                sequence = after(self.at.seq(k), 1)[0]
                if sequence != self.last_sequence[k]:
                    self.last_sequence[k] = sequence
                    self.command(k, self.value(self.at.fmt, after(self.at.cmd(k), self.at.w)),
                                 sequence)
        super().setValues(fc_as_hex, address, values)
        if table == "c":
            self.set_status()


async def serve(args):
    host, _, port = args.listen.rpartition(":")
    controller = Controller(args)
    context = ModbusServerContext(slaves={args.unit: controller}, single=False)
    server = ModbusTcpServer(context, address=(host, int(port)), allow_reuse_address=True)
    task = asyncio.create_task(server.serve_forever())
    await server.serving
    bound = server.server.sockets[0].getsockname()[1]
    specimen = f"{args.stiffness_matrix or args.stiffness} N/mm"
    print(f"modbus_server: listening on {host}:{bound} (unit {args.unit}, {args.actuators} x "
          f"{args.actuator} actuator, specimen {specimen}, p0 {args.p0_mm} mm, {args.type}, "
          f"{args.word_order})", flush=True)
    await task


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--listen", default="127.0.0.1:5020", help="HOST:PORT (port 0: any free)")
    p.add_argument("--unit", type=int, default=1, help="unit id answered (default 1)")
    p.add_argument("--stiffness", type=float, default=5.25, help="specimen stiffness [N/mm]")
    p.add_argument("--actuators", type=int, default=1, help="number of actuators (default 1)")
    p.add_argument("--stiffness-matrix", metavar="K11,K12;K21,K22",
                   help="coupled specimen in actuator coordinates [N/mm] (default: --stiffness "
                        "on the diagonal)")
    p.add_argument("--p0-mm", default="0", help="position of zero force [mm] (a list: one per "
                   "actuator)")
    p.add_argument("--start-mm", default=None, help="start position [mm] (p0; a list: one per "
                   "actuator)")
    p.add_argument("--type", choices=("float32", "float64"), default="float32",
                   help="command, position and force registers")
    p.add_argument("--stride-holding", type=int, help="holding stride (default: packed)")
    p.add_argument("--stride-input", type=int, help="input stride (default: packed)")
    p.add_argument("--stride-coils", type=int, help="coil stride (default 2; 0: shared)")
    p.add_argument("--holding-base", help="each actuator's first holding register (a list)")
    p.add_argument("--input-base", help="each actuator's first input register (a list)")
    p.add_argument("--coil-base", help="each actuator's enable coil (a list; hold: the next)")
    p.add_argument("--lab-time-address", type=int,
                   help="input register of the lab time (default: after the last block)")
    p.add_argument("--stroke-mm", type=float, default=150.0, help="|command| limit [mm]")
    p.add_argument("--actuator", choices=("ideal", "lag"), default="ideal")
    p.add_argument("--time-constant-ms", type=float, default=20.0, help="lag time constant")
    p.add_argument("--settle-mm", type=float, default=0.001, help="lag: settled within [mm]")
    p.add_argument("--overhead-ms", type=float, default=0.0, help="lab time per command [ms]")
    p.add_argument("--ack-delay-ms", type=float, default=0.0, help="wall delay of the ack")
    p.add_argument("--word-order", choices=("high_first", "low_first"), default="high_first")
    p.add_argument("--lab-time", action="store_true", help="lab time at input 6-7 (uint32 ms)")
    p.add_argument("--fault", action="append", default=[], metavar="KIND@N[/A]",
                   help=f"test fault at command N of actuator A (default 1); KIND: "
                        f"{', '.join(KINDS)}")
    p.add_argument("--offset-mm", type=float, default=50.0,
                   help="offset@N: measured minus actual position [mm] (default 50)")
    p.add_argument("--log-commands", metavar="FILE",
                   help="append 'SEQUENCE COMMAND_MM' for every command received")
    p.add_argument("--verbose", action="store_true", help="pymodbus log on stderr")
    args = p.parse_args()
    logging.basicConfig(level=logging.INFO if args.verbose else logging.CRITICAL)
    if not args.verbose:
        logging.disable(logging.CRITICAL)  # refused test commands are expected, not news
    try:
        asyncio.run(serve(args))
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
