# Type stubs of cmbrl.results.
from typing import Any, Optional, Sequence, Union

from ._common import _Path

def read_runs(dirs: Union[_Path, Sequence[_Path]]) -> list[dict[str, Any]]: ...
def report(dirs: Union[_Path, Sequence[_Path]], out: _Path, window: Optional[int] = ...,
           reference: Optional[_Path] = ..., complete: bool = ...) -> dict[str, Any]: ...
