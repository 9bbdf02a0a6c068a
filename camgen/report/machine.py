"""The machine's part of report.html (mechanism job ``machine``): the timing diagram of its
followers against machine angle, phases marked, and the shaft torque with the flywheel's speed."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.report.format import FigureMaker, thin
from camgen.report.model import FloatArray, SectionData, json_number, json_object

if TYPE_CHECKING:
    from camgen.report.model import MechanismReport

__all__ = ["MachineSection", "machine_section"]


@dataclass(frozen=True)
class MachineSection(SectionData):
    """What the machine's section draws: machine angles (rad), each follower's timing
    (:class:`camgen.jobs.machine.FollowerTiming`), the curves asked for, the speed (rad/s), the
    shaft torque (N*m), the speed with the flywheel (rad/s), the motor's torque (N*m) and the cams
    whose torque is summed."""

    angles: FloatArray
    timings: tuple[Any, ...]
    curves: tuple[str, ...]
    omega: float
    torque: FloatArray
    speed: FloatArray
    motor_torque: float
    torque_cams: tuple[str, ...]


_WHAT = {"displacement": ("s / stroke", 0), "velocity": ("v / peak |v|", 1), "acceleration": ("a / peak |a|", 2)}


def machine_section(Figure: FigureMaker, mechanism: "MechanismReport") -> str:
    """The timing diagram (each curve scaled by its own peak so that mm and deg share one axis),
    the shaft torque and the motor's, and the speed the flywheel leaves."""
    data = mechanism.section
    assert isinstance(data, MachineSection)
    figures = mechanism.figures
    fly = json_object(figures.get("flywheel"))
    parts = ["<h2>Machine: cams on one shaft</h2>",
             f"<p class='note'>{len(data.timings)} followers at {json_number(figures['rpm']):g} rpm; dashed lines where each cam is "
             "at its cam angle 0 (machine angle = -phase). Torque summed over " + (", ".join(data.torque_cams) or "no cam") + "; flywheel "
             f"{json_number(fly['inertia_kg_m2']):.6g} kg*m^2 for Cs = {json_number(figures['speed_fluctuation']):g} "
             f"(energy swing {json_number(fly['energy_swing_J']):.6g} J, Norton ch. 11).</p>"]
    deg = np.degrees(data.angles)
    keep = thin(deg.size, 1440)
    fig = Figure(figsize=(10, 2.6 + 1.2 * len(data.curves)))
    axes = fig.subplots(len(data.curves), 1)
    axes = axes if isinstance(axes, (list, tuple, np.ndarray)) else [axes]
    for ax, curve in zip(axes, data.curves):
        label, order = _WHAT[curve]
        for t in data.timings:
            values = (t.s - t.s.min(), t.ds, t.d2s)[order]
            peak = float(np.max(np.abs(values)))
            line = ax.plot(deg[keep], (values / peak if peak > 0 else values)[keep], width=1, label=t.name)
            ax.vline(math.degrees((-t.phase) % (2 * math.pi)), color=line.get_color(), dash="--", width=0.7)
        ax.xlabel("machine angle (deg)")
        ax.ylabel(label)
        ax.title(f"timing diagram: {curve}", font_size=9)
        ax.legend(font_size=7)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    fig = Figure(figsize=(10, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(deg[keep], data.torque[keep], width=1, label="shaft torque")
    ax1.hline(data.motor_torque, color="tab:red", dash="--", width=0.8, label="motor with flywheel (mean)")
    ax1.xlabel("machine angle (deg)")
    ax1.ylabel("torque (N*m)")
    ax1.title("camshaft torque of the machine", font_size=9)
    ax1.legend(font_size=7)
    ax2.plot(deg[keep], (data.speed * 60.0 / (2 * math.pi))[keep], width=1, label="with the flywheel")
    ax2.hline(data.omega * 60.0 / (2 * math.pi), color="k", dash="--", width=0.8, label="machine speed")
    ax2.xlabel("machine angle (deg)")
    ax2.ylabel("speed (rpm)")
    ax2.title("shaft speed the flywheel leaves", font_size=9)
    ax2.legend(font_size=7)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    return "\n".join(parts)
