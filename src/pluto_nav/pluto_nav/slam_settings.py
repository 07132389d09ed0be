"""Tunables and per-scan results of the slamModule's filter (:class:`.slam_filter.SlamFilter`)."""

from __future__ import annotations

import dataclasses
import math

from .slam_association import AssociationSettings
from .slam_merge import MergeSettings

__all__ = ['SlamSettings', 'SlamUpdate']


@dataclasses.dataclass(frozen=True)
class SlamSettings:
    """Tunables of :class:`SlamFilter` (defaults in brackets)."""

    #: Factor on the odometry increments' covariance [2]: a map error is permanent, so the
    #: filter takes the odometry as somewhat worse than its model says rather than trust an
    #: unlucky increment and map the next walls askew.
    odometry_inflation: float = 2.0
    #: Data association (:class:`.slam_association.AssociationSettings`).
    association: AssociationSettings = AssociationSettings()
    #: Merging landmarks (:class:`.slam_merge.MergeSettings`).
    merge: MergeSettings = MergeSettings()
    #: A match whose residual after the joint correction lies beyond the chi-square (2 dof)
    #: quantile at this probability is dropped [0.99999].
    consistency_probability: float = 0.99999
    #: m: lines farther than this from the laser are not used [30].  Far walls are what keeps
    #: the position along a corridor; the lines' covariances grow with range as they should.
    max_range: float = 30.0
    #: m: extents grow, and landmarks start, only from what lies this close to the laser [30].
    extent_range: float = 30.0
    #: m: a matched line extends an extent only where it continues it within this gap [0.3].
    extend_gap: float = 0.3
    #: A new landmark needs a line of this many points and this length (m) [8, 0.6].
    new_min_points: int = 8
    new_min_length: float = 0.6
    #: Scans in a row with fewer than ``slam_filter.MIN_MATCHES_TO_MAP`` matches after which lines
    #: with no match start landmarks anyway (the robot has come where the map has nothing) [3].
    adrift_scans: int = 3
    #: Matches that confirm a landmark; a tentative one unseen for this many scans goes [4, 10].
    confirm_matches: int = 4
    tentative_scans: int = 10
    #: Ends are anchored to confirmed walls crossing at this angle or more, this close (m), whose
    #: own wall reaches as close to the crossing [30 deg, 0.3]: only at a corner.  An end tied to
    #: a crossing farther off moves with every correction of that other wall (a door jamb tied to
    #: a room's wall seen through the door, 0.5 m away, was moved 20 cm into the door gap).
    anchor_min_angle: float = math.radians(30.0)
    anchor_radius: float = 0.3
    #: m: radius of the local area of the compressed filter [2].
    zone_radius: float = 2.0
    #: m: shorter walls are left out of :meth:`SlamFilter.walls` [0.3].
    min_wall_length: float = 0.3

    def __post_init__(self) -> None:
        if not self.odometry_inflation >= 1.0:
            raise ValueError('odometry_inflation must be 1 or more')
        if not 0.0 < self.extent_range <= self.max_range:
            raise ValueError('extent_range must be positive and not above max_range')
        if self.confirm_matches < 1 or self.tentative_scans < 1 or self.new_min_points < 2:
            raise ValueError('confirm_matches and tentative_scans must be >= 1, '
                             'new_min_points >= 2')


@dataclasses.dataclass(frozen=True)
class SlamUpdate:
    """What one :meth:`SlamFilter.update` did.

    :ivar lines: lines offered.
    :ivar matched: lines used to correct pose and map.
    :ivar rejected: matches dropped as inconsistent with the others.
    :ivar ambiguous: lines left out because two landmarks fitted them about equally well.
    :ivar added: landmarks started.
    :ivar merged: landmarks merged into others.
    :ivar pruned: tentative landmarks dropped.
    :ivar landmarks: landmarks after the update; ``active`` of them in the local area.
    :ivar committed: whether the full covariance was brought up to date (the robot left its
        local area).
    :ivar nis: normalised innovation squared of the matches used, per degree of freedom (NaN
        without matches).
    """

    lines: int
    matched: int
    rejected: int
    ambiguous: int
    added: int
    merged: int
    pruned: int
    landmarks: int
    active: int
    committed: bool
    nis: float
