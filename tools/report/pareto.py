"""The Pareto front of (time, error) pairs, both minimised."""


def pareto_front(pairs):
    """Indices of the pairs on the front, in increasing time (and so decreasing error).

    A pair is on the front when no other pair is at least as good in both time and error and better
    in one. Of identical pairs only the first is kept, so the front has one entry per distinct trade-off.
    """
    order = sorted(range(len(pairs)), key=lambda i: (pairs[i][0], pairs[i][1], i))
    front = []
    for i in order:
        # Sorted by time, a pair is dominated exactly when an earlier pair has an error <= its own.
        if not front or pairs[i][1] < pairs[front[-1]][1]:
            front.append(i)
    return front
