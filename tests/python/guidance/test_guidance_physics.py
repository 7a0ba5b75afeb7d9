"""The cable, the walker and the robot behave as the models say (signs, slack, energy)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from yoyogait.guidance import GuidanceConfig, GuidedWalker, GuidePath, HumanModel, cable_force, simulate
from yoyogait.synthetic import SUBJECTS

L0, K = 1.0, 300.0


@pytest.mark.parametrize("d", [0.2, 0.8, 0.999999, 1.0])
def test_a_slack_cable_pulls_nothing(d):
    """At or below its rest length the cable's force is exactly zero, whatever the stretch rate."""
    robot = (0.3 * d, 0.4 * d, math.sqrt(max(d * d - 0.25 * d * d, 0.0)))
    assert math.isclose(math.dist(robot, (0, 0, 0)), d, rel_tol=1e-9)
    assert cable_force(robot, (0.0, 0.0, 0.0), L0, K, 10.0, 5.0) == (0.0, 0.0, 0.0)


def test_a_taut_cable_pulls_the_hand_towards_the_robot_and_the_robot_towards_the_hand():
    """Taut: the force on the hand points along robot - hand with magnitude k (|l| - l0)."""
    hand = np.array([1.0, 2.0, 1.0])
    robot = hand + np.array([0.9, 0.3, 0.5])
    f = np.array(cable_force(robot, hand, L0, K))
    length = np.linalg.norm(robot - hand)
    assert np.allclose(f, K * (length - L0) * (robot - hand) / length)
    assert f @ (robot - hand) > 0


def test_the_cable_force_on_the_robot_is_minus_the_gradient_of_the_elastic_energy():
    """-f_c on the robot equals -dU/dp_R for U = k (|l| - l0)^2 / 2 (a conservative spring), by finite differences."""
    hand = np.array([0.0, 0.0, 1.0])
    robot = np.array([0.95, 0.2, 1.45])

    def energy(p):
        stretch = max(np.linalg.norm(p - hand) - L0, 0.0)
        return 0.5 * K * stretch**2

    eps = 1e-6
    grad = np.array([(energy(robot + eps * e) - energy(robot - eps * e)) / (2 * eps) for e in np.eye(3)])
    on_robot = -np.array(cable_force(robot, hand, L0, K))
    assert np.allclose(on_robot, -grad, rtol=1e-5, atol=1e-8)


def test_a_cable_cannot_push():
    """A taut cable shortening fast enough for the damping to exceed the spring gives zero tension, never a push."""
    hand = (0.0, 0.0, 0.0)
    robot = (1.01, 0.0, 0.0)
    assert cable_force(robot, hand, L0, K, 10.0, -1.0) == (0.0, 0.0, 0.0)
    assert cable_force(robot, hand, L0, K, 10.0, 0.1)[0] > cable_force(robot, hand, L0, K)[0] > 0


def test_an_unpulled_walker_only_slows_down():
    """Without cable force the walker's intended speed never increases (the damper only takes energy out)."""
    walker = GuidedWalker(SUBJECTS[0], HumanModel(), 0.0, 0.0, 0.0)
    walker.vx, walker.vy = 1.2, 0.3
    speeds = []
    for _ in range(2000):
        walker.step(0.002, 0.0, 0.0)
        speeds.append(walker.speed_mps)
    assert np.all(np.diff(speeds) <= 0) and speeds[-1] < 0.05


def test_a_steady_pull_gives_the_speed_force_over_damping():
    """A constant force F leads the walker to F / B_H in the direction of the force, stepping at its cadence law."""
    subject = SUBJECTS[1]
    model = HumanModel()
    walker = GuidedWalker(subject, model, 0.0, 0.0, 0.0)
    force = model.nominal_force_n
    for _ in range(5000):  # 10 s, over 10 time constants
        walker.step(0.002, 0.0, force)
    assert walker.vy == pytest.approx(force / model.damping_ns_per_m(subject), rel=1e-3)
    assert abs(walker.vx) < 1e-9 and walker.heading == pytest.approx(math.pi / 2)
    assert walker.cadence_hz == pytest.approx(subject.step_frequency_hz, rel=1e-3)


def test_the_guided_walker_follows_the_robot_and_the_robot_respects_its_speed_limit():
    """With the true velocity fed back, the walker reaches the goal of a straight path; the robot never
    exceeds its speed limit; the cable is slack exactly when it pulls nothing."""
    cfg = GuidanceConfig(max_speed_mps=1.5)
    straight = GuidePath("straight", np.array([[0.0, 0.0], [5.0, 0.0]]), np.ones(2), np.zeros(2))
    run = simulate(straight, SUBJECTS[0], "truth", config=cfg)
    assert math.isfinite(run.goal_s)
    assert np.linalg.norm(run.robot_v_mps, axis=1).max() <= 1.5 + 1e-12
    assert np.all(run.tension_n[run.slack] == 0.0) and np.all(run.tension_n[~run.slack] > 0.0)
