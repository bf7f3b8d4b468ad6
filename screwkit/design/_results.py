"""The results of :func:`screwkit.design.synthesize_motion`: ranked PMs and the search's counts."""

from __future__ import annotations

from dataclasses import dataclass

from ..synthesis import model_yaml
from ._verify import Verdict

__all__ = ["SynthesizedPM", "TypeSynthesis"]


@dataclass(frozen=True)
class SynthesizedPM:
    """One verified PM of :func:`synthesize_motion`.

    Attributes
    ----------
    rank : int
        1 is the best.
    name : str
        As the literature writes it: ``"3-PRS"``, ``"3-RRPaR"``, ``"2-UPU+SPR"``
        (several listed PMs may share it: their leg types differ).
    variant : str
        Unique in a listing, with the leg types' names: ``"3UPU/couple"``,
        ``"3RRPaR/t.t.t.t"`` (the model's name, and the file ``--write`` writes).
    string : str
        The PM string (``"3UPU"``, ``"2UPU+SPR"``).
    motion : str
    legs : tuple of str
        Leg type per vertex.
    symmetric : bool
    geometry : str
        The standard geometry it was verified on.
    joints : int
        Equivalent 1-DOF joints of all legs.
    actuators : tuple of str
        The legs' strings with the actuated joint marked (``"U_PU"``).
    actuator_position : float
        Mean 1-based position of the actuated letter in its leg (1: every actuator on
        the base).
    condition_home : float
        Length-normalised condition number of ``J`` at home.
    verdict : Verdict
        The engine's verification (mobility at every checked pose, finite invariant).
    definition : dict
        The ``pms:`` entry (write it with :meth:`model_yaml`).
    passive : tuple of str
        The passive legs' types (no actuator; ``actuators`` lists the actuated legs only).
    leg_definitions : tuple of dict
        The ``legs:`` entries of its leg types that the packaged catalog lacks (generated,
        user and extra ones): :meth:`model_yaml` writes them.
    origins : tuple of str
        Per leg: ``"catalog"``, ``"extra"``, ``"user"`` or ``"generated"``.
    """

    rank: int
    name: str
    string: str
    motion: str
    legs: tuple
    symmetric: bool
    geometry: str
    joints: int
    actuators: tuple
    actuator_position: float
    condition_home: float
    verdict: Verdict
    definition: dict
    passive: tuple = ()
    variant: str = ""
    leg_definitions: tuple = ()
    origins: tuple = ()

    def model_yaml(self) -> str:
        """The model YAML: the definitions of the leg types the packaged catalog lacks,
        then the PM (``screwkit.load_pm`` reads it, ``screwkit analyze FILE`` analyses it);
        a passive leg is declared ``{leg: NAME, passive: true}``."""
        return model_yaml(self.variant or self.name, self.definition, self.leg_definitions)

    def to_dict(self) -> dict:
        v = self.verdict
        return {"rank": self.rank, "name": self.name, "variant": self.variant,
                "string": self.string, "motion": self.motion, "legs": list(self.legs),
                "origins": list(self.origins), "symmetric": self.symmetric,
                "geometry": self.geometry, "joints": self.joints,
                "actuators": list(self.actuators), "actuator_position": self.actuator_position,
                "condition_home": self.condition_home,
                "verified_poses": [{"pose": c.pose, "dof": c.dof, "motion_type": c.motion_type,
                                    "translations": c.translations, "rotations": c.rotations,
                                    "condition_number": c.condition_number} for c in v.checks],
                "path_samples_reached": v.reached, "singular_on_path": v.singular_on_path,
                "finite_check": v.finite, "finite_motion": v.motion, "notes": list(v.notes),
                "passive_legs": list(self.passive), "definition": self.definition,
                "leg_definitions": list(self.leg_definitions)}


@dataclass(frozen=True)
class TypeSynthesis:
    """Result of :func:`synthesize_motion`.

    Attributes
    ----------
    motion : MotionPattern
    n_legs : int
    pool : tuple of LegKind
        The leg types whose constraint systems fit the motion: the catalog's, then the
        generated ones.
    listed : tuple of SynthesizedPM
        The verified PMs, ranked (at most ``limit``).
    verified : int
        Verified PMs before the limit.
    tried : int
        Candidate compositions.
    rejected : tuple of (str, str)
        ``(name, reason)`` of the candidates that reached the engine and failed.
    screened_out : int
        Candidates whose legs did not span the complementary system at home on any
        geometry (or could not be built there by their rules).
    not_verified : int
        Candidates that passed the screen but were not verified: the budget
        ``max_verified`` of engine verifications was spent.
    pruned : int
        Asymmetric candidates not tried: mixes of leg types whose symmetric PMs are not
        among the best verified ones (see :func:`synthesize_motion`).
    generated : int
        Generated leg types in the pool.
    engine_runs : int
        Engine verifications (a candidate on one geometry).
    """

    motion: object
    n_legs: int
    pool: tuple
    listed: tuple
    verified: int
    tried: int
    rejected: tuple
    screened_out: int
    not_verified: int = 0
    pruned: int = 0
    generated: int = 0
    engine_runs: int = 0

    def __len__(self) -> int:
        return len(self.listed)

    def names(self) -> list:
        """The listed PMs' literature names (``"3-PRS"``)."""
        return [p.name for p in self.listed]

    def variants(self) -> list:
        """The listed PMs' unique names (``"3PRS/n.t.-"``)."""
        return [p.variant for p in self.listed]

    def to_dict(self) -> dict:
        m = self.motion
        return {"motion": m.name, "dof": m.dof, "independent": list(m.independent),
                "complement": m.complement, "legs": self.n_legs,
                "pool": [{"name": k.name, "string": k.marked, "forces": k.forces,
                          "couples": k.couples, "origin": k.origin} for k in self.pool],
                "generated_legs": self.generated, "tried": self.tried,
                "screened_out": self.screened_out, "not_verified": self.not_verified,
                "pruned": self.pruned, "engine_runs": self.engine_runs,
                "verified": self.verified, "listed": [p.to_dict() for p in self.listed],
                "rejected": [{"name": n, "reason": r} for n, r in self.rejected],
                "units": {"length": "cm", "angle": "deg"}}
