"""Error-against-time charts of sweep points with their Pareto front, as PNG and SVG."""
import itertools

import matplotlib

matplotlib.use('Agg')  # files only: no display in CI
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

# The named profiles the lead marks on every chart keep one look across charts and scenes.
LABEL_STYLES = {
    'desktop': dict(marker='s', color='tab:blue'),
    'mobile': dict(marker='^', color='tab:orange'),
    'auto': dict(marker='*', color='tab:red'),
}
_OTHER_STYLES = [dict(marker=m, color=c) for m, c in
                 zip('DPXvh', ('tab:purple', 'tab:brown', 'tab:pink', 'tab:olive', 'tab:cyan'))]


def label_styles(labels):
    """A marker and colour per label: the fixed ones for known profiles, the rest in turn."""
    others = itertools.cycle(_OTHER_STYLES)
    return {label: LABEL_STYLES.get(label) or next(others) for label in sorted(labels)}


def error_time_chart(measured, front, title, time_label, out_base):
    """Draws every measurement (sweep_data.Measurement), the front (indices into measured, by
    increasing time) as a step line, and labelled points with their own markers.
    Writes out_base + '.png' and '.svg' and returns both paths."""
    fig, ax = plt.subplots(figsize=(7.5, 4.8), dpi=110)
    ax.scatter([m.time_ms for m in measured], [m.error for m in measured], s=22, color='0.55',
               label=f'sweep points ({len(measured)})', zorder=2)
    front_points = [measured[i] for i in front]
    # steps-post: each front point's error holds until the next, faster-is-worse point's time.
    ax.plot([m.time_ms for m in front_points], [m.error for m in front_points], drawstyle='steps-post',
            color='black', linewidth=1.4, marker='o', markersize=4, label='Pareto front', zorder=3)
    labelled = {m.point.label for m in measured if m.point.label}
    annotated = {}  # (time, error) -> labels written there, to stack the text of coincident points
    for label, style in label_styles(labelled).items():
        points = [m for m in measured if m.point.label == label]
        ax.scatter([m.time_ms for m in points], [m.error for m in points], s=110, edgecolors='black',
                   linewidths=0.8, label=label, zorder=4, **style)
        for m in points:
            stacked = annotated.setdefault((m.time_ms, m.error), [])
            ax.annotate(label, (m.time_ms, m.error), textcoords='offset points',
                        xytext=(7, 5 + 10 * len(stacked)), fontsize=8)
            stacked.append(label)
    ax.set_yscale('log')
    ax.set_xlabel(time_label)
    ax.set_ylabel('mean relative luminance error')
    ax.set_title(title)
    ax.grid(True, which='both', linewidth=0.4, alpha=0.5)
    ax.legend(fontsize=8, loc='best')
    fig.tight_layout()
    paths = [f'{out_base}.png', f'{out_base}.svg']
    for path in paths:
        fig.savefig(path)
    plt.close(fig)
    return paths
