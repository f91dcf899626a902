"""The "settings chosen" of a report: the plan of a `--profile auto` run, or a profile's keys.

A plan is {"choices": [{"key", "value", "reason"}, ...], ...}, alone in a file or under "plan" (or
"extra"."plan") of a render's report.json. Any other JSON object is read as a profile, shown as its
dotted keys (the form sweep axes use) without reasons.
"""
import json
from dataclasses import dataclass
from pathlib import Path


class PlanError(ValueError):
    pass


@dataclass
class SettingsChosen:
    source: str          # where the settings came from, for the section's caption
    kind: str            # "plan" or "profile"
    rows: list           # (key, value as text, reason or '')
    details: list        # (key, value as text): a plan's fields other than its choices


def _text(value):
    return value if isinstance(value, str) else json.dumps(value)


def find_plan(doc):
    """The plan object in a plan file or a report.json, or None."""
    if 'choices' in doc:
        return doc
    for holder in (doc, doc.get('extra') or {}):
        if isinstance(holder.get('plan'), dict):
            return holder['plan']
    return None


def flatten(obj, prefix=''):
    """(dotted key, value) of every leaf of a JSON object, in file order."""
    for key, value in obj.items():
        path = f'{prefix}.{key}' if prefix else key
        if isinstance(value, dict) and value:
            yield from flatten(value, path)
        else:
            yield path, value


def plan_settings(plan, source):
    choices = plan.get('choices')
    if not isinstance(choices, list):
        raise PlanError(f'{source}: the plan\'s "choices" is not a list')
    rows = []
    for i, c in enumerate(choices):
        if not isinstance(c, dict) or 'key' not in c:
            raise PlanError(f'{source}: plan choice {i} has no "key"')
        rows.append((str(c['key']), _text(c.get('value')), str(c.get('reason') or '')))
    details = [(k, _text(v)) for k, v in plan.items() if k != 'choices']
    return SettingsChosen(source=source, kind='plan', rows=rows, details=details)


def load_settings(path):
    try:
        doc = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise PlanError(f'{path}: {e}') from e
    if not isinstance(doc, dict):
        raise PlanError(f'{path}: not a JSON object')
    plan = find_plan(doc)
    if plan is not None:
        return plan_settings(plan, str(path))
    if doc.get('format') == 'cpurender-run-report':
        raise PlanError(f'{path}: a render report without a plan (only `--profile auto` writes one)')
    return SettingsChosen(source=str(path), kind='profile',
                          rows=[(k, _text(v), '') for k, v in flatten(doc)], details=[])
