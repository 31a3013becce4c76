"""Test campaigns: one logical scenario, many concrete runs, and what they found.

An OSC2 scenario is a logical scenario: its ranges and constraints describe
many concrete tests. A campaign runs N of them — the witnesses of seeds
``S .. S+N-1`` (``random``), or witnesses chosen to fill the scenario's
``cover`` bins (``cover``) — on a local process pool or a Ray cluster,
optionally with a system under test in the loop (:mod:`osc2runner.sut`), and
writes per run its files and KPIs, per campaign the pass rate, the coverage,
the worst runs and the KPIs over the parameters::

    from osc2runner.campaign import CampaignOptions, run_campaign
    result = run_campaign(CampaignOptions("examples/cut_in_and_stop.osc", runs=40, out="c"))
    result.summary["pass_rate"], result.folder / "report.html"

Modules: ``campaign`` (the flow), ``plan`` (seeds and bins), ``steering``
(cover items and directed witnesses), ``worker`` (check once, run per seed),
``pool`` and ``ray_engine`` (engines), ``kpis``, ``summary``, ``parameters``
(swept and derived parameters), ``spread`` (how evenly runs cover them),
``failures`` (pass/fail map, failure boundary, triage), ``outputs``, ``charts``
and ``report``. The command is ``osc2run FILE --runs N``; see docs/campaigns.md.
"""

from __future__ import annotations

from typing import Any

__all__ = ["CampaignOptions", "CampaignResult", "run_campaign"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from osc2runner.campaign import campaign

        return getattr(campaign, name)
    raise AttributeError(name)
