"""ergosim/Allocation-v0: the Gymnasium contract, determinism, and the same simulation as ``ergosim run``."""

from __future__ import annotations

import dataclasses

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import ergosim.gym
from ergosim import api
from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment.csv_files import write_allocations
from ergosim.experiment.runner import run_subject
from ergosim.gym import ENV_ID, AllocationEnv, evaluate, mode_policy, random_policy

pytestmark = pytest.mark.filterwarnings("ignore::UserWarning:gymnasium")


@pytest.fixture(scope="module")
def scenario():
    return api.load("multi-subject", {"repetitions": "2", "subjects": "1"})


@pytest.mark.slow
def test_registered_and_passes_the_env_checker(scenario):
    env = gym.make(ENV_ID, scenario=scenario, repetitions=1)
    assert isinstance(env.unwrapped, AllocationEnv)
    check_env(env.unwrapped, skip_render_check=True)
    assert ergosim.gym.__all__ and all(hasattr(ergosim.gym, name) for name in ergosim.gym.__all__)


@pytest.mark.slow
def test_steps_are_deterministic_for_a_seed(scenario):
    runs = []
    for _ in range(2):
        env = AllocationEnv(scenario, repetitions=2)
        rng = np.random.default_rng(7)
        obs, info = env.reset(seed=3)
        trace = [obs]
        done = False
        while not done:
            obs, reward, done, _, info = env.step(int(rng.choice(np.flatnonzero(info["action_mask"]))))
            trace += [obs, reward]
        runs.append(trace)
    assert len(runs[0]) == len(runs[1]) > 4
    for a, b in zip(*runs, strict=True):
        if isinstance(a, dict):
            for key in a:
                np.testing.assert_array_equal(a[key], b[key])
        else:
            assert a == b


@pytest.fixture(scope="module")
def replayed(scenario):
    """mode -> (the env after an episode of that mode's own decisions, seed 5, 2 repetitions; the episode);
    made once per mode for the tests below."""
    made = {}

    def episode(mode: str):
        if mode not in made:
            env = AllocationEnv(scenario, mode=mode, repetitions=2)
            made[mode] = env, evaluate(env, mode_policy, seed=5)
        return made[mode]

    return episode


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["hrc", "kwear-lookahead"])
def test_a_mode_replayed_through_the_env_is_its_run(scenario, replayed, mode):
    """The paper's rule (and the look-ahead) deciding through the env: the allocations, the KWear of every
    tick and the rewards' integral are those of ``ergosim run`` (run_subject) for the same seed."""
    env, episode = replayed(mode)
    ran = run_subject(scenario, 0, 5, (mode,)).runs[mode]
    got = env.result
    rows = [dataclasses.astuple(a) for a in got.allocations]
    assert rows == [dataclasses.astuple(a) for a in ran.allocations]
    np.testing.assert_array_equal(got.ticks.rows, ran.ticks.rows)
    assert episode.kwear_integral == pytest.approx(float(ran.ticks.kwear.sum()) * ran.dt_tick, rel=1e-12)
    assert episode.steps == sum(a.status != "pruned" for a in ran.allocations)


@pytest.mark.slow
def test_the_papers_rule_through_the_env_writes_the_allocations_of_ergosim_run(replayed, tmp_path):
    """``ergosim run`` itself (the CLI, in this process) against the paper's rule replayed through the env:
    the same allocations.csv, byte for byte."""
    out = tmp_path / "run"
    assert main(["run", "multi-subject", "--subjects", "1", "--reps", "2", "--mode", "hrc", "--seed", "5",
                 "--jobs", "1", "--quiet", "--no-plots", "--out", str(out)]) == 0
    env, _ = replayed("hrc")
    write_allocations(tmp_path / "env.csv", env.result.allocations)
    cli = (out / "allocations.csv").read_text()
    assert len(cli.splitlines()) > 8 and (tmp_path / "env.csv").read_text() == cli


@pytest.mark.slow
def test_masked_choice_changes_nothing_and_the_episode_ends(scenario):
    env = AllocationEnv(scenario, repetitions=1, invalid_penalty=2.0)
    obs, info = env.reset(seed=0)
    bad = int(np.flatnonzero(info["action_mask"] == 0)[0])
    again, reward, terminated, _, info2 = env.step(bad)
    assert reward == -2.0 and not terminated and info2["invalid_action"]
    for key in obs:
        np.testing.assert_array_equal(obs[key], again[key])
    episode = evaluate(env, random_policy(np.random.default_rng(1)), seed=0)
    assert episode.steps >= 5 and episode.ret < 0
    with pytest.raises(gym.error.ResetNeeded):
        env.step(0)


def test_parallel_execution_is_refused():
    with pytest.raises(ConfigError, match="sequential"):
        AllocationEnv("gearbox", overrides={"execution": "parallel"})
