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

A command is taken when the sequence register changes. The controller moves (instantly, or
with the lag until within --settle-mm), samples the force k (x - p0), and then publishes
position, force and the ack (after --ack-delay-ms of wall time, to exercise polling). It
refuses a command (Modbus exception 4) while not enabled, while holding, or beyond the stroke.

Usage (by hand, for a dry run; Ctrl-C stops it):
  python3 tests/transfer/modbus_server.py --listen 127.0.0.1:5020 --stiffness 5.25
  hybridtest run examples/rotor/modbus.yaml --bench 127.0.0.1:5020 --out results/modbus.csv

Test faults (N counts commands from 1): --fault silent@N (never acks command N and later),
fault@N (sets the fault bit instead of acking N), exception@N (answers the write of N with
Modbus exception 4), mute@N (stops answering anything from command N on), holding@N (acks N
but reports holding from then on, as a controller that holds on its own), disabled@N (acks N
but clears the enabled bit), offset@N (from N on, the measured position is --offset-mm off the
position the actuator reached: a following error or a position sensor fault).

--log-commands FILE appends one line "SEQUENCE COMMAND_MM" for every command received (before
it is checked), so a test can assert the largest step between consecutive commands. A
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

CMD, SEQ = 0, 2                  # holding registers
POS, FORCE, ACK, STATUS, LAB = 0, 2, 4, 5, 6   # input registers
ENABLE, HOLD = 0, 1              # coils
ENABLED, FAULT, HOLDING = 1, 2, 4  # status bits
KINDS = ("silent", "fault", "exception", "mute", "holding", "disabled", "offset")


class Controller(ModbusSlaveContext):
    """The register space plus the actuator and specimen behind it."""

    def __init__(self, args):
        super().__init__(co=ModbusSequentialDataBlock(0, [False] * 16),
                         di=ModbusSequentialDataBlock(0, [False] * 16),
                         hr=ModbusSequentialDataBlock(0, [0] * 16),
                         ir=ModbusSequentialDataBlock(0, [0] * 16), zero_mode=True)
        self.args = args
        self.faults = {}
        for spec in args.fault:
            kind, _, at = spec.partition("@")
            if kind not in KINDS or not at.isdigit():
                raise SystemExit(f"modbus_server: --fault {spec}: expected KIND@N with KIND "
                                 f"one of {', '.join(KINDS)}")
            self.faults[kind] = int(at)
        self.position = args.start_mm if args.start_mm is not None else args.p0_mm  # [mm]
        self.lab_time = 0.0          # [s]
        self.commands = 0
        self.last_sequence = 0
        self.status = 0
        self.forced_holding = False  # holding@N: reports holding whatever the coil says
        self.forced_disabled = False  # disabled@N: reports not enabled whatever the coil says
        self.offset_mm = 0.0         # offset@N: measured position minus actual position [mm]
        self.log = open(args.log_commands, "a", encoding="utf-8") if args.log_commands else None
        self.publish(self.position, 0)

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

    def publish(self, position, ack):
        force = self.args.stiffness * (position - self.args.p0_mm)  # [N]
        measured = position + self.offset_mm
        self.set_input(POS, self.words("f", measured) + self.words("f", force) + [ack])
        if self.args.lab_time:
            self.set_input(LAB, self.words("I", int(round(self.lab_time * 1e3)) % 2**32))
        self.set_status()

    def set_status(self):
        coils = super().getValues(1, ENABLE, 2)
        enabled = coils[0] and not self.forced_disabled
        holding = coils[1] or self.forced_holding
        self.status = (self.status & FAULT) | (ENABLED if enabled else 0) | \
            (HOLDING if holding else 0)
        self.set_input(STATUS, [self.status])

    # -- the actuator -------------------------------------------------------------------------
    def move(self, target):
        """Moves to `target` [mm]; returns the settled position and adds its lab time."""
        a = self.args
        self.lab_time += a.overhead_ms * 1e-3
        if a.actuator == "ideal":
            return target
        gap = self.position - target
        tau = a.time_constant_ms * 1e-3
        steps = 0 if abs(gap) <= a.settle_mm else math.ceil(
            tau * math.log(abs(gap) / a.settle_mm) / 1e-3)
        self.lab_time += steps * 1e-3
        return target + gap * math.exp(-steps * 1e-3 / tau)

    def command(self, target, sequence):
        self.commands += 1
        n, faults = self.commands, self.faults
        if self.log:
            self.log.write(f"{sequence} {target!r}\n")
            self.log.flush()
        if faults.get("mute", 0) and n >= faults["mute"]:
            while True:          # stop answering: the client's response timeout must fire
                time.sleep(3600)
        if faults.get("exception", 0) == n:
            raise RuntimeError(f"command {n} refused (test fault)")
        if not self.status & ENABLED or self.status & HOLDING:
            raise RuntimeError("command refused: not enabled, or holding")
        if not math.isfinite(target) or abs(target) > self.args.stroke_mm:
            raise RuntimeError(f"command {target} mm refused: beyond the stroke")
        if faults.get("silent", 0) and n >= faults["silent"]:
            return
        if faults.get("fault", 0) == n:
            self.status |= FAULT
            self.set_input(STATUS, [self.status])
            return
        self.position = self.move(target)
        self.forced_holding |= faults.get("holding", 0) == n
        self.forced_disabled |= faults.get("disabled", 0) == n
        if faults.get("offset", 0) and n >= faults["offset"]:
            self.offset_mm = self.args.offset_mm
        if self.args.ack_delay_ms > 0:
            asyncio.get_event_loop().call_later(self.args.ack_delay_ms * 1e-3, self.publish,
                                                self.position, sequence)
        else:
            self.publish(self.position, sequence)

    # -- the Modbus side ----------------------------------------------------------------------
    def setValues(self, fc_as_hex, address, values):
        table = self.decode(fc_as_hex)
        if table == "h":
            regs = super().getValues(3, CMD, 3)
            regs[address:address + len(values)] = values
            sequence = regs[SEQ]
            if sequence != self.last_sequence:
                self.last_sequence = sequence
                self.command(self.value("f", regs[CMD:CMD + 2]), sequence)
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
    print(f"modbus_server: listening on {host}:{bound} (unit {args.unit}, {args.actuator} "
          f"actuator, specimen {args.stiffness} N/mm, p0 {args.p0_mm} mm, "
          f"{args.word_order})", flush=True)
    await task


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--listen", default="127.0.0.1:5020", help="HOST:PORT (port 0: any free)")
    p.add_argument("--unit", type=int, default=1, help="unit id answered (default 1)")
    p.add_argument("--stiffness", type=float, default=5.25, help="specimen stiffness [N/mm]")
    p.add_argument("--p0-mm", type=float, default=0.0, help="position of zero force [mm]")
    p.add_argument("--start-mm", type=float, default=None, help="start position [mm] (p0)")
    p.add_argument("--stroke-mm", type=float, default=150.0, help="|command| limit [mm]")
    p.add_argument("--actuator", choices=("ideal", "lag"), default="ideal")
    p.add_argument("--time-constant-ms", type=float, default=20.0, help="lag time constant")
    p.add_argument("--settle-mm", type=float, default=0.001, help="lag: settled within [mm]")
    p.add_argument("--overhead-ms", type=float, default=0.0, help="lab time per command [ms]")
    p.add_argument("--ack-delay-ms", type=float, default=0.0, help="wall delay of the ack")
    p.add_argument("--word-order", choices=("high_first", "low_first"), default="high_first")
    p.add_argument("--lab-time", action="store_true", help="lab time at input 6-7 (uint32 ms)")
    p.add_argument("--fault", action="append", default=[], metavar="KIND@N",
                   help=f"test fault at command N; KIND: {', '.join(KINDS)}")
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
