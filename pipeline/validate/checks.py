"""One validation check: a quantity, its expected value (an analytic or
established reference), the measured one, and the tolerance that decides."""
from dataclasses import asdict, dataclass


@dataclass
class Check:
    case: str        # the validation case, e.g. "Chung & Ooi 1: normal impact of equal disks"
    quantity: str    # what is compared, e.g. "contact duration"
    expected: float
    measured: float
    tolerance: float  # see `kind`
    unit: str = ""
    kind: str = "rel"  # rel: |m - e| <= tol |e|;  abs: |m - e| <= tol;  below: m <= e;  above: m >= e
    reference: str = ""  # where the expected value comes from

    @property
    def passed(self) -> bool:
        m, e, t = self.measured, self.expected, self.tolerance
        if m != m:  # NaN: nothing measured
            return False
        if self.kind == "rel":
            return abs(m - e) <= t * abs(e)
        if self.kind == "abs":
            return abs(m - e) <= t
        if self.kind == "below":
            return m <= e
        if self.kind == "above":
            return m >= e
        raise ValueError(f"unknown check kind {self.kind}")

    def tolerance_text(self) -> str:
        return {"rel": f"±{100 * self.tolerance:.3g} %", "abs": f"±{self.tolerance:.3g}",
                "below": "at most", "above": "at least"}[self.kind]

    def row(self) -> dict:
        return {**asdict(self), "passed": self.passed}
