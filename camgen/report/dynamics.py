"""report.html's cam-follower dynamics of one cam: the curves the dynamics stage computed
(:class:`camgen.report.model.DynamicsCurves`), drawn with :mod:`camgen.report.svgplot`.

Six panels against cam angle at the scene's speed: the contact force (both faces of a yoke)
with the jump margin; its direction, the pressure angle; the camshaft torque with its limit;
the power; the Hertz contact stress with the allowable; and the smallest contact force against
cam speed, which crosses the jump margin at the jump speed (a yoke: the follower force and the
side force on the guide instead).  Nothing is computed here beyond unit-free thinning.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.report.format import FigureMaker, thin

if TYPE_CHECKING:
    from camgen.report.model import CamReport, CompliantCurves, FrictionCurves

__all__ = ["ROUNDING", "compliant_section", "dynamics_section", "friction_section"]

_LIMIT = {"color": "tab:red", "dash": "--", "width": 0.8}
#: A mean power below this fraction of the peak is shown as 0 in the plot's title (rounding of a zero integral).
ROUNDING = 1e-9


#: The two contacts of a form-closed train as the plots name them, by cam form (a yoke's faces
#: otherwise): contact 1 pushes the follower out (+s), contact 2 pulls it back.
FORM_CLOSED_CONTACTS = {
    "": ("face 1", "face 2", "the yoke's two faces"),
    "groove": ("inner wall", "outer wall", "the groove's two walls"),
    "conjugate": ("roller A on cam A", "roller B on cam B", "the pair's two rollers"),
    "barrel": ("lower wall", "upper wall", "the groove's two walls (at the mean radius)"),  # BDYN: kinds/barrel_dynamics.py
    "barrel rib": ("upper roller on the rib's upper face", "lower roller on its lower face",
                   "the rib's two faces (at the mean radius)"),  # ROSC: kinds/barrel_rib_dynamics.py
}


def dynamics_section(Figure: FigureMaker, cam: "CamReport") -> str:
    """The dynamics part of a cam's section of report.html (an empty string without dynamics)."""
    res = cam.dynamics
    if res is None:
        return ""
    form = res.closure == "form"
    form_name = "barrel rib" if cam.form == "barrel" and "rib" in cam.figures else cam.form  # ROSC: a barrel's rib
    one, two, both = FORM_CLOSED_CONTACTS.get(form_name, FORM_CLOSED_CONTACTS[""])
    figures = cam.figures.get("dynamics", {})
    assert isinstance(figures, Mapping)
    keep = thin(res.theta.size, 1200)
    deg = np.degrees(res.theta)[keep]
    fig = Figure(figsize=(10, 8.4))
    axes = fig.subplots(3, 2)
    (ax_f, ax_p), (ax_t, ax_w), (ax_h, ax_s) = axes
    # contact force
    if form:
        assert res.contact_force_2 is not None  # a form-closed train's second contact
        ax_f.plot(deg, res.contact_force[keep], color="tab:blue", width=1, label=f"{one} (pushes the follower out)")
        ax_f.plot(deg, res.contact_force_2[keep], color="tab:orange", width=1, label=f"{two} (pulls it back)")
        ax_f.title(f"contact force on {both}", font_size=8)
        ax_f.legend(font_size=7)
    else:
        ax_f.plot(deg, res.contact_force[keep], color="tab:blue", width=1, label="contact force")
        ax_f.hline(res.jump_margin, label=f"jump margin {res.jump_margin:g} N", **_LIMIT)
        jump = ("never jumps" if math.isinf(res.jump_rpm) else "off the cam at rest" if res.jump_rpm == 0
                else f"jumps at {res.jump_rpm:.5g} rpm")
        ax_f.title(f"contact force at {res.rpm:g} rpm (margin dashed); {jump}", font_size=8)
    ax_f.hline(0.0, color="#737373", width=0.6)
    ax_f.ylabel("contact force (N)", font_size=8)
    # its direction
    ax_p.plot(deg, np.degrees(res.pressure_angle)[keep], color="tab:purple", width=1)
    ax_p.ylabel("pressure angle (deg)", font_size=8)
    ax_p.title("direction of the contact force: the pressure angle (from the follower's motion)", font_size=8)
    # torque and power
    ax_t.plot(deg, res.torque[keep], color="tab:green", width=1)
    limit = res.torque_limit
    if limit is not None:
        for sign in (1, -1):
            ax_t.hline(sign * limit, **_LIMIT)
    ax_t.hline(0.0, color="#737373", width=0.6)
    ax_t.ylabel("camshaft torque (N*m)", font_size=8)
    ax_t.title(f"camshaft torque: peak {res.torque_peak:.4g}, RMS {res.torque_rms:.4g} N*m"
               + (f"; limit {limit:g} N*m dashed" if limit is not None else ""), font_size=8)
    ax_w.plot(deg, res.power[keep], color="tab:brown", width=1)
    ax_w.hline(0.0, color="#737373", width=0.6)
    ax_w.ylabel("power (W)", font_size=8)
    mean = res.mean_power if abs(res.mean_power) > ROUNDING * res.power_peak else 0.0  # no damping: 0 up to rounding
    ax_w.title(f"shaft power: peak {res.power_peak:.4g} W, RMS {res.power_rms:.4g} W, mean {mean:.4g} W", font_size=8)
    # contact stress
    if res.hertz_stress is None and res.hertz_stress_2 is None:
        ax_h.text(0.5, 0.5, "no Hertz stress: a sharp knife edge (or no material)", anchor="middle", coords="axes")
    else:
        if res.hertz_stress is not None:
            ax_h.plot(deg, res.hertz_stress[keep], color="tab:blue", width=1, label=one if form else None)
        if res.hertz_stress_2 is not None:
            ax_h.plot(deg, res.hertz_stress_2[keep], color="tab:orange", width=1, label=two)
        allowable = res.allowable_stress
        if allowable is not None:
            ax_h.hline(allowable, label=f"allowable {allowable:g} MPa", **_LIMIT)
        ax_h.title(f"Hertz contact stress: peak {res.hertz_peak:.4g} MPa"
                   + (f"; allowable {allowable:g} MPa dashed" if allowable is not None else ""), font_size=8)
        if form:
            ax_h.legend(font_size=7)
    ax_h.ylabel("contact stress (MPa)", font_size=8)
    ax_h.xlabel("cam angle (deg)", font_size=8)
    # the jump margin against speed (force closure) or the follower and side forces (yoke)
    if res.speed_rpm is not None and res.speed_min_force is not None:
        ax_s.plot(res.speed_rpm, res.speed_min_force, color="tab:blue", width=1)
        ax_s.hline(res.jump_margin, **_LIMIT)
        ax_s.vline(res.rpm, color="k", dash=":", width=0.8)
        if math.isfinite(res.jump_rpm) and 0 < res.jump_rpm <= res.speed_rpm[-1]:
            ax_s.vline(res.jump_rpm, color="tab:red", dash=":", width=0.8)
        ax_s.xlabel("cam speed (rpm)", font_size=8)
        ax_s.ylabel("smallest contact force (N)", font_size=8)
        ax_s.title(f"jump margin against speed: this speed {res.rpm:g} rpm dotted"
                   + (f", jump at {res.jump_rpm:.5g} rpm" if math.isfinite(res.jump_rpm) and res.jump_rpm > 0 else ""), font_size=8)
    else:
        ax_s.plot(deg, res.follower_force[keep], color="tab:blue", width=1, label="along the motion")
        ax_s.plot(deg, res.side_force[keep], color="tab:orange", width=1, label="across it (guide load)")
        ax_s.ylabel("force on the follower (N)", font_size=8)
        ax_s.xlabel("cam angle (deg)", font_size=8)
        ax_s.title("net force of the cam on the follower", font_size=8)
        ax_s.legend(font_size=7)
    for ax in (ax_f, ax_p, ax_t, ax_w):
        ax.xlabel("cam angle (deg)", font_size=8)
    fig.suptitle(f"{cam.name}: follower dynamics at {res.rpm:g} rpm ({res.motion}, "
                 f"{'form-closed yoke' if form else 'spring-loaded'})", font_size=9)
    from camgen.report.design import dynamics_rows

    rows = dynamics_rows(figures)
    compliant = compliant_section(Figure, res.compliant, res.rpm) if res.compliant is not None else ""  # issue 25 item 2
    friction = friction_section(Figure, res.friction, res.rpm, res.torque_limit) if res.friction is not None else ""  # items 3, 4
    return (f"<h3>Dynamics at {res.rpm:g} rpm</h3><div class='fig'>{fig.to_svg()}</div>{compliant}{friction}"
            "<p class='note'>Rigid follower train, frictionless contact (Rothbart, Cam Design Handbook, ch. 8): contact force "
            "= (inertia + damping + spring + preload + load + weight) over the cosine of the pressure angle; torque from the power "
            "balance; Hertz line-contact stress (Rothbart eq. 9.11) with the profile's radius of curvature at the contact.</p>"
            f"<table class='figures'><caption>Dynamics figures at {res.rpm:g} rpm</caption><thead><tr><th>quantity</th><th>value</th>"
            f"<th>unit</th></tr></thead><tbody>{rows}</tbody></table>")


# ---- compliant follower train (issue 25 item 2) --------------------------------------------
def compliant_section(Figure: FigureMaker, res: "CompliantCurves", rpm: float) -> str:
    """The compliant train's plots: the dynamic against the rigid contact force, the dynamic
    error with the residual amplitudes at the dwell starts, and the law's acceleration spectrum
    by harmonic with the natural frequency marked."""
    keep = thin(res.theta.size, 1200)
    deg = np.degrees(res.theta)[keep]
    fig = Figure(figsize=(10, 5.6))
    (ax_f, ax_e), (ax_s, ax_r) = fig.subplots(2, 2)
    ax_f.plot(deg, res.rigid_force[keep], color="#737373", width=1, dash="--", label="rigid train")
    ax_f.plot(deg, res.contact_force[keep], color="tab:blue", width=1, label="compliant train")
    ax_f.hline(0.0, color="#737373", width=0.6)
    ax_f.legend(font_size=7)
    ax_f.xlabel("cam angle (deg)", font_size=8)
    ax_f.ylabel("contact force (N)", font_size=8)
    ax_f.title(f"dynamic contact force at {rpm:g} rpm: peak {np.max(res.contact_force):.4g} N "
               f"({np.max(res.contact_force) / np.max(res.rigid_force):.4g} x rigid), least {np.min(res.contact_force):.4g} N",
               font_size=8)
    two = res.natural_frequencies is not None  # a two-mass train: the tool's error, the cam side's beside it
    modes: tuple[float, ...] = res.natural_frequencies if res.natural_frequencies is not None else (res.natural_frequency,)
    if two and res.cam_side_error is not None:
        ax_e.plot(deg, res.cam_side_error[keep], color="#737373", width=0.8, label="cam-side mass")
    ax_e.plot(deg, res.error[keep], color="tab:purple", width=1, label="tool mass" if two else None)
    if two:
        ax_e.legend(font_size=7)
    ax_e.hline(0.0, color="#737373", width=0.6)
    ax_e.xlabel("cam angle (deg)", font_size=8)
    ax_e.ylabel(f"{'tool' if two else 'follower'} - cam ({res.error_unit})", font_size=8)
    ax_e.title("dynamic displacement error x - y (the train's deflection and vibration)", font_size=8)
    harmonic = np.arange(1, res.spectrum.size + 1)
    for n, amplitude in zip(harmonic, res.spectrum):
        ax_s.plot([n, n], [0.0, amplitude], color="tab:blue", width=1.2)
    ratios = [f / res.turn_frequency for f in modes]
    for ratio in ratios:
        if ratio <= harmonic[-1] + 1:
            ax_s.vline(ratio, color="tab:red", dash="--", width=0.8)
    ax_s.xlabel(f"harmonic of the turn ({res.turn_frequency:.4g} Hz each)", font_size=8)
    ax_s.ylabel(f"acceleration amplitude ({res.spectrum_unit})", font_size=8)
    ax_s.title(("the law's acceleration spectrum; natural frequenc" + ("ies " if two else "y ")) + " and ".join(
        f"{f:.4g} Hz = harmonic {ratio:.4g} " + ("(dashed)" if ratio <= harmonic[-1] + 1 else "(beyond the plot)")
        for f, ratio in zip(modes, ratios)), font_size=8)
    if res.residual.size:
        ax_r.plot(np.degrees(res.dwell_theta), res.residual, color="tab:blue", marker="o", dash="none")
        if res.residual_limit is not None:
            ax_r.hline(res.residual_limit, label=f"limit {res.residual_limit:g} mm", **_LIMIT)
            ax_r.legend(font_size=7)
        ax_r.xlim(0.0, 360.0)
        ax_r.ylim(0.0, None)
        ax_r.title(f"residual vibration at each dwell's start: largest {np.max(res.residual):.4g} mm", font_size=8)
    else:
        ax_r.text(0.5, 0.5, "no dwell: no residual vibration after a rise or return", anchor="middle", coords="axes")
    ax_r.xlabel("cam angle (deg)", font_size=8)
    ax_r.ylabel("residual amplitude (mm)", font_size=8)
    if two:
        fig.suptitle(f"two-mass compliant follower train: natural frequencies {modes[0]:.5g} and {modes[-1]:.5g} Hz", font_size=9)
        model = ("two degrees of freedom: the train's stiffness between the cam contact and the cam-side mass, the "
                 "follower's own stiffness between it and the tool mass, a damper across each, Koster 1974")
    else:
        fig.suptitle(f"compliant follower train: natural frequency {res.natural_frequency:.5g} Hz, damping ratio "
                     f"{res.damping_ratio:.4g}", font_size=9)
        model = ("one degree of freedom: the train's stiffness and damping between the cam contact and the follower's mass, "
                 "Koster 1974")
    return (f"<div class='fig'>{fig.to_svg()}</div><p class='note'>Compliant follower train ({model}): its periodic steady "
            "state over a turn, solved exactly for the linear model; where the dynamic contact force would fall below 0 the "
            "follower leaves the cam.</p>")
# ---- end compliant -------------------------------------------------------------------------



# ---- friction, loads and contact life (issue 25 items 3, 4) ---------------------------------
def friction_section(Figure: FigureMaker, res: "FrictionCurves", rpm: float, torque_limit: float | None) -> str:
    """The friction's plots, each where it applies: the camshaft torque with and without friction
    (with the torque limit), the guide's side load and bushing reactions against the binding limit,
    the roller's drive torque against the traction the contact holds (its slip margin), the
    sub-surface shear, and the Hertz half-width and shear depth against the case depth asked for."""
    keep = thin(res.theta.size, 1200)
    deg = np.degrees(res.theta)[keep]
    panels = []
    if res.torque is not None and res.torque_with_friction is not None and res.friction_torque is not None:
        torque, total, friction = res.torque, res.torque_with_friction, res.friction_torque

        def draw_torque(ax: Any) -> None:
            ax.plot(deg, torque[keep], color="#737373", width=1, dash="--", label="without friction")
            ax.plot(deg, total[keep], color="tab:green", width=1, label="with friction")
            ax.plot(deg, friction[keep], color="tab:orange", width=0.8, label="friction's share")
            if torque_limit is not None:
                for sign in (1, -1):
                    ax.hline(sign * torque_limit, **_LIMIT)
            ax.hline(0.0, color="#737373", width=0.6)
            ax.ylabel("camshaft torque (N*m)", font_size=8)
            ax.title(f"camshaft torque with friction: peak {np.max(np.abs(total)):.4g} N*m (without "
                     f"{np.max(np.abs(torque)):.4g})" + (f"; limit {torque_limit:g} N*m dashed" if torque_limit is not None else ""),
                     font_size=8)
            ax.legend(font_size=7)

        panels.append(draw_torque)
    if res.side_load is not None:
        side = res.side_load

        def draw_guide(ax: Any) -> None:
            ax.plot(deg, np.abs(side)[keep], color="tab:purple", width=1, label="side load |F_x|")
            if res.guide_near is not None and res.guide_far is not None:
                ax.plot(deg, res.guide_near[keep], color="tab:blue", width=1, label="near bushing |R1|")
                ax.plot(deg, res.guide_far[keep], color="tab:cyan", width=1, label="far bushing |R2|")
                ax.title(f"guide loads: side {np.max(np.abs(side)):.4g} N, bushings {np.max(res.guide_near):.4g} and "
                         f"{np.max(res.guide_far):.4g} N at most", font_size=8)
            else:
                ax.title(f"side load on the guide (F_axial tan phi): peak {np.max(np.abs(side)):.4g} N", font_size=8)
            ax.ylim(0.0, None)
            ax.ylabel("force across the stem (N)", font_size=8)
            ax.legend(font_size=7)

        panels.append(draw_guide)
    if res.binding is not None and res.guide_friction is not None:
        binding, mu_g = res.binding, res.guide_friction

        def draw_binding(ax: Any) -> None:
            ax.plot(deg, binding[keep], color="tab:blue", width=1, label=f"mu_g (|R1| + |R2|) / F_axial, mu_g {mu_g:g}")
            ax.hline(1.0, label="binds at 1", **_LIMIT)
            ax.ylim(0.0, None)
            ax.ylabel("bushing friction / axial force", font_size=8)
            ax.title(f"guide binding margin: the bushings' friction up to {np.max(binding):.4g} x the axial force", font_size=8)
            ax.legend(font_size=7)

        panels.append(draw_binding)
    if res.pin_torque is not None and res.roller_drive_torque is not None and res.traction_limit is not None:
        pin, drive, traction = res.pin_torque, res.roller_drive_torque, res.traction_limit

        def draw_slip(ax: Any) -> None:
            ax.plot(deg, traction[keep], label="traction limit mu_c F R", **_LIMIT)
            ax.plot(deg, drive[keep], color="tab:blue", width=1, label="torque to turn the roller")
            ax.plot(deg, pin[keep], color="tab:orange", width=0.8, dash=":", label="pin friction mu_p F r_pin")
            ax.ylim(0.0, None)
            ax.ylabel("torque on the roller (N*mm)", font_size=8)
            ax.title(f"roller slip margin: torque to turn it up to {res.slip_peak:.4g} x the traction (skids above 1)", font_size=8)
            ax.legend(font_size=7)

        panels.append(draw_slip)
    if res.shear is not None and res.half_width is not None and res.shear_depth is not None:
        shear, half, depth = res.shear, res.half_width, res.shear_depth

        def draw_shear(ax: Any) -> None:
            ax.plot(deg, shear[keep], color="tab:red", width=1)
            ax.ylim(0.0, None)
            ax.ylabel("sub-surface shear (MPa)", font_size=8)
            ax.title(f"sub-surface maximum shear 0.30 p_max (Johnson 4.2): peak {np.max(shear):.4g} MPa", font_size=8)

        def draw_depth(ax: Any) -> None:
            ax.plot(deg, half[keep], color="tab:blue", width=1, label="Hertz half-width b")
            ax.plot(deg, depth[keep], color="tab:red", width=1, label="depth of the maximum shear 0.78 b")
            if res.case_depth is not None:
                ax.hline(res.case_depth, label=f"case depth asked for {res.case_depth:.4g} mm", **_LIMIT)
            ax.ylim(0.0, None)
            ax.ylabel("depth below the surface (mm)", font_size=8)
            ax.title(f"contact half-width and shear depth: deepest {np.max(depth):.4g} mm", font_size=8)
            ax.legend(font_size=7)

        panels += [draw_shear, draw_depth]
    if not panels:
        return ""
    cols = 1 if len(panels) == 1 else 2
    rows = -(-len(panels) // cols)
    fig = Figure(figsize=(10 if cols == 2 else 6, 2.8 * rows + 0.3))
    axes = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    for draw, ax in zip(panels, axes):
        draw(ax)
        ax.xlabel("cam angle (deg)", font_size=8)
    for ax in axes[len(panels):]:  # an odd number of panels: say what the blank one would hold
        ax.text(0.5, 0.5, "(no further friction plot for these keys)", anchor="middle", coords="axes")
    fig.suptitle(f"friction, loads and contact fatigue at {rpm:g} rpm", font_size=9)
    return (f"<div class='fig'>{fig.to_svg()}</div><p class='note'>First-order friction (Coulomb's mu N with N the "
            "frictionless contact force; the friction does not feed back into it): each friction's torque on the camshaft "
            "from the power it dissipates; the guide's bushing reactions from the stem's statics; Hertz line contact "
            "(Johnson, Contact Mechanics, 4.2) for the half-width and the sub-surface shear.</p>")
# ---- end friction -------------------------------------------------------------------------
