"""``slam_score``: how good a trajectory is, by the public SLAM benchmark's metric.

    slam_score TRAJ RELATIONS              Kümmerle et al.'s relation metric
    slam_score TRAJ --reference REF        relative pose error against a reference trajectory

``TRAJ`` is a TUM file (``offline_nav --trajectory``); ``RELATIONS`` a relation file (``t1 t2 dx
dy dz roll pitch dyaw``); ``REF`` a TUM file or a graph log (``VERTEX2`` + ``ROBOTLASER1``).  Prints
the number of pairs scored, the mean and standard deviation of the translational (m) and
rotational (deg) error (:mod:`pluto_nav.slam_metric`).  Exit status 2 for a file that cannot be
read, 1 when no pair could be scored.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from .slam_metric import MetricError, load_relations, load_trajectory, relation_error, relative_pose_error

__all__ = ['main']


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='slam_score', description=__doc__.split('\n\n')[0])
    parser.add_argument('trajectory', help='the trajectory, TUM format')
    parser.add_argument('relations', nargs='?', help='ground-truth relations (Kuemmerle et al. 2009)')
    parser.add_argument('--reference', help='a reference trajectory (TUM or graph log)')
    parser.add_argument('--min-distance', type=float, default=0.3, help='m, reference pairs at least this far apart')
    parser.add_argument('--max-distance', type=float, default=2.0, help='m, and at most this far')
    args = parser.parse_args(list(sys.argv[1:] if argv is None else argv))
    if (args.relations is None) == (args.reference is None):
        parser.error('give RELATIONS or --reference REF (one of them)')
    try:
        stamps, poses = load_trajectory(args.trajectory)
        if args.relations is not None:
            score = relation_error(stamps, poses, load_relations(args.relations))
        else:
            score = relative_pose_error(stamps, poses, *load_trajectory(args.reference),
                                        min_distance=args.min_distance, max_distance=args.max_distance)
    except MetricError as error:
        print(f'slam_score: {error}', file=sys.stderr)
        return 2
    print(score.line())
    return 0 if score.count else 1


if __name__ == '__main__':
    sys.exit(main())
