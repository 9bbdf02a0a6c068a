"""The scene-key reference, generated from the schema: ``camgen keys`` prints it and
``docs/scene-keys.md`` in the repository holds the same text (a test keeps the file current)."""
from __future__ import annotations

from camgen.schema import Key, key_reference_rows

TITLE = "# camgen scene keys\n"

HEADER = """Generated from the schema by `camgen keys` (do not edit by hand). Lengths are millimetres and
angles degrees in scene files. "changes" names what a key changes: profile (every file of the
cam's shape: DXF, point and lift tables, meshes, STEP, G-code), pitch (the DXF PITCH layer),
body (bore and keyway: DXF, meshes, STEP), thickness (meshes, STEP, G-code depth), gcode,
dxf, tables (the lift table), motion (the follower table at speed), tolerance (every flattened
output), files, mechanism (its report section and files), report (report.json and report.html
only). A key given where it
would change nothing is refused with an error that says why.
"""


def _table(keys: tuple[Key, ...]) -> str:
    lines = ["| key | value | default | changes | what it is |", "| --- | --- | --- | --- | --- |"]
    for name, value, default, effect, doc in key_reference_rows(keys):
        cells = (f"`{name}`", value, f"`{default}`" if default not in ("-", "required") else default, effect, doc)
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines) + "\n"


def _names(keys: tuple[Key, ...]) -> str:
    return ", ".join(f"`{k.name}`" for k in keys)


def _kind_sections() -> list[tuple[str, str, str]]:
    """(motion, form, section name) of every cam type: each motion with its own (default) form
    in the section named after the motion, then with every other form that realises it in the
    section ``<motion>/<form>``."""
    from camgen.kinds import forms_of, kind_names
    from camgen.motions import get_motion

    out = []
    for name in kind_names():
        default = get_motion(name).default_form
        out.append((name, default, name))
        out += [(name, form, f"{name}/{form}") for form in forms_of(name) if form != default]
    return out


def _selector(name: str, form: str) -> str:
    from camgen.motions import get_motion

    own = form == get_motion(name).default_form
    return f'kind = "{name}"' + ("" if own else f', form = "{form}"')


def index() -> str:
    """The keys of every table in a few lines (the reference's first lines: ``camgen keys | head``)."""
    from camgen.jobs import get_job, job_names
    from camgen.kinds import get_kind
    from camgen.outputs import machining_keys, output_keys

    lines = ["Every table and its keys (each is explained in its section below; `camgen keys SECTION` prints one section):",
             "",
             "- top level: `name`, `[output]`, `[machining]`, `[cams.<name>]` (one or more), `[mechanisms.<name>]`, `[sweep]`, `[tolerance]`",
             f"- `[output]` (section output): {_names(output_keys())}",
             f"- `[machining]` (section machining): {_names(machining_keys())}"]
    for name, form, section in _kind_sections():
        keys = get_kind(name, form).keys
        lines.append(f"- `[cams.<name>]` with {_selector(name, form)} (section {section}): `kind`, {_names(keys)}")
        for key in keys:
            sub = getattr(key.type, "keys", None)
            if sub:
                lines.append(f"  - each `[[cams.<name>.{key.name}]]`: {_names(sub)}")
    for name in job_names():
        lines.append(f"- `[mechanisms.{name}]` (section {name}): {_names(get_job(name).keys)}")
    return "\n".join(lines) + "\n"


def sections() -> dict[str, str]:
    """Section name -> its Markdown text: "output", "machining", every kind, every mechanism, "sweep", "tolerance"."""
    from camgen.forms import get_form
    from camgen.jobs import get_job, job_names
    from camgen.kinds import get_kind
    from camgen.outputs import OUTPUTS, machining_keys, output_keys

    out: dict[str, str] = {}
    formats = "\n".join(f"- `{f.name}`: `{f.files}`: {f.description}" for f in OUTPUTS.values())
    out["output"] = f"## [output]\n\n{_table(output_keys())}\nFormats:\n\n{formats}\n"
    out["machining"] = "## [machining]\n\nG-code settings (output format `ngc`).\n\n" + _table(machining_keys())
    for name, form, section in _kind_sections():
        kind = get_kind(name, form)
        summary = kind.summary if section == name else f"{kind.summary}, realised as a {form} cam: {get_form(form).summary}"
        text = f"## [cams.<name>] with {_selector(name, form)}\n\n{summary}.\n\n{_table(kind.keys)}"
        for key in kind.keys:
            sub = getattr(key.type, "keys", None)
            if sub:
                text += f"\nEach `[[cams.<name>.{key.name}]]` table:\n\n{_table(sub)}"
        out[section] = text
    for name in job_names():
        job = get_job(name)
        out[name] = f"## [mechanisms.{name}]\n\n{job.summary}.\n\n{_table(job.keys)}"
        for key in job.keys:  # a list of tables (the machine's [[mechanisms.machine.cams]])
            sub = getattr(key.type, "keys", None)
            if sub:
                out[name] += f"\nEach `[[mechanisms.{name}.{key.name}]]` table:\n\n{_table(sub)}"
    from camgen.study.space import SWEEP_REFERENCE

    out["sweep"] = SWEEP_REFERENCE
    from camgen.study.tolerance_settings import TOLERANCE_REFERENCE

    out["tolerance"] = TOLERANCE_REFERENCE
    return out


def reference(section: str | None = None) -> str:
    """The whole reference, or one section of it (KeyError for an unknown section).

    The whole reference opens with the index of every table's keys, so that its first lines
    (``camgen keys | head``) name keys; the conventions and the tables follow."""
    parts = sections()
    if section is not None:
        return parts[section]
    scene = ("## The scene file\n\nTop-level keys: `name` (the output folder's name; default: the scene file's name), "
             "`[output]`, `[machining]`, `[cams.<name>]` (one or more), `[mechanisms.<name>]`, `[sweep]` (read by "
             "`camgen sweep`), `[tolerance]` (read by `camgen tolerance`).\n")
    return TITLE + "\n" + index() + "\n" + HEADER + "\n" + scene + "\n" + "\n".join(parts.values())
