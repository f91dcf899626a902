"""The Pareto front of (time, error) pairs (tools/report/pareto.py)."""
import itertools
import random
import unittest

import report_paths  # noqa: F401  (puts tools/report on sys.path)
from pareto import pareto_front


def dominated(a, b):
    """True when b is at least as good as a in both and better in one: the definition, checked by brute force."""
    return b[0] <= a[0] and b[1] <= a[1] and b != a


class ParetoFrontTest(unittest.TestCase):
    def test_empty_and_single(self):
        self.assertEqual(pareto_front([]), [])
        self.assertEqual(pareto_front([(3.0, 0.1)]), [0])

    def test_hand_made_front_in_increasing_time(self):
        pairs = [(26, 0.020), (20, 0.050), (24, 0.030), (22, 0.045), (25, 0.044), (23, 0.025)]
        # 24 ms / 0.030 and 25 ms / 0.044 are both beaten by 23 ms / 0.025.
        self.assertEqual(pareto_front(pairs), [1, 3, 5, 0])

    def test_a_faster_and_better_point_dominates_every_other(self):
        self.assertEqual(pareto_front([(5, 0.5), (1, 0.1), (3, 0.3), (2, 0.2)]), [1])

    def test_equal_time_keeps_only_the_lower_error(self):
        self.assertEqual(pareto_front([(2, 0.3), (2, 0.1), (1, 0.5)]), [2, 1])

    def test_equal_error_keeps_only_the_faster(self):
        self.assertEqual(pareto_front([(4, 0.1), (2, 0.1), (1, 0.5)]), [2, 1])

    def test_identical_pairs_keep_the_first(self):
        self.assertEqual(pareto_front([(1.5, 0.04), (1.5, 0.04), (3, 0.02), (3, 0.02)]), [0, 2])

    def test_order_of_input_does_not_change_the_front(self):
        pairs = [(1, 0.9), (2, 0.5), (3, 0.6), (4, 0.1), (5, 0.2)]
        expected = {pairs[i] for i in pareto_front(pairs)}
        for perm in itertools.permutations(pairs):
            self.assertEqual({perm[i] for i in pareto_front(list(perm))}, expected)

    def test_matches_the_definition_on_random_points(self):
        rng = random.Random(27)
        for _ in range(200):
            # Few distinct values, so ties in time, in error and in both are common.
            pairs = [(rng.randint(0, 8), rng.randint(0, 8) / 10) for _ in range(rng.randint(1, 25))]
            front = pareto_front(pairs)
            on_front = {pairs[i] for i in front}
            expected = {p for p in pairs if not any(dominated(p, q) for q in pairs)}
            self.assertEqual(on_front, expected, pairs)
            self.assertEqual(len(front), len(on_front), 'a trade-off listed twice')
            times = [pairs[i][0] for i in front]
            errors = [pairs[i][1] for i in front]
            self.assertEqual(times, sorted(times))
            self.assertEqual(errors, sorted(errors, reverse=True))


if __name__ == '__main__':
    unittest.main()
