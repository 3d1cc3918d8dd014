"""The sum of every order of scattering from the first ones: reduced rank extrapolation.

From order 3 on, each order of the multiple-scattering stage is the same linear map A of the order before
(``multiple.multiple_scattering``): the orders are x_2, A x_2, A^2 x_2, ... and their sum T solves T = x_2 + A T.
Reduced rank extrapolation (RRE; Sidi, "Vector Extrapolation Methods with Applications", SIAM 2017, ch. 1) takes,
after k + 1 orders, the combination s_k = sum_j gamma_j T_j of the partial sums T_j = x_2 + ... + x_{j+2} with
sum_j gamma_j = 1 that minimises the norm of its residual x_2 + A s_k - s_k = sum_j gamma_j x_{j+3}, over the
Krylov space the orders span: the same solution as GMRES on (I - A) T = x_2, from the orders the stage computes
anyway. Where the orders fall slowly (an optically thick atmosphere, a bright ground: A's largest eigenvalues near
1) the geometric tail of the last order (``multiple.geometric_tail``) holds only once the orders' shape has settled,
which takes as many orders as the sum itself; RRE needs far fewer. Each wavelength is a system of its own (its own
gamma); the residual is weighed by 1 / T_k per texel (floored at ``FLOOR`` of the wavelength's largest texel), so
that every texel counts by its relative error.

Error estimate: the residual r of s_k bounds its error by ||(I - A)^-1|| ||r||, with ||(I - A)^-1|| about
1 / (1 - q), q the ratio of the last two orders' sums (A's largest eigenvalue): ``OrderSum.error`` is
max |r| / (1 - q), relative to T_k per texel. On the draft tables of random atmospheres 1 and 4 and the
exo-co2-thick preset (against 200-300 orders; gamma solved on every texel), it was above the largest relative
error of s_k at every k, by 2-10 times; where it stopped them (gamma on the sketch) the error was 0.04-0.33%
against a tolerance of 1% (docs/tables.md).
"""
import numpy as np

#: The residual's weight 1 / T_k per texel, with T_k floored at this share of its wavelength's largest texel.
FLOOR = 1e-3
#: The texels per wavelength on which gamma is solved (a fixed random subset where there are more; the residual and
#: the error estimate take every texel).
SKETCH = 1 << 16
#: q's ceiling in 1 / (1 - q).
Q_MAX = 0.999


class OrderSum:
    """The orders of scattering x_2, x_3, ... as they come (:meth:`add`), each a set of arrays whose last axis
    holds the wavelengths: the scattering tables S (..., 2W: molecules then particles, both halves a wavelength's),
    the irradiance E (..., W) and the top row's density (..., 2W); the sum of all of them by RRE (:meth:`sum`), and
    its estimated relative error per wavelength (:meth:`error`)."""

    def __init__(self, n_wavelengths, seed=0):
        self.W = n_wavelengths
        self.orders = []                   # per order: (S per wavelength (W, texels) float32, E, top float32)
        self.shape = None                  # S's shape
        self.sketch = None                 # (W, n, capacity): the orders' S on the sketched texels
        self.sums = []                     # per order: S summed per wavelength (W,)
        self.partial = None                # T_k of S per wavelength (W, texels), float64
        self.rng = np.random.default_rng(seed)
        self.picks = None
        self.gamma = None

    def _channel(self, S, w):
        """Wavelength w's texels of S (..., 2W), molecules then particles, flat."""
        return np.concatenate([S[..., w].ravel(), S[..., self.W + w].ravel()])

    def add(self, S, E, top):
        """Order ``len(self.orders) + 2``: S (..., 2W), E (..., W), top (..., 2W)."""
        if self.picks is None:
            size = 2 * S[..., 0].size
            self.picks = np.sort(self.rng.choice(size, SKETCH, replace=False)) if size > SKETCH else np.arange(size)
        channels = np.stack([self._channel(S, w) for w in range(self.W)]).astype(np.float32)     # (W, texels)
        k = len(self.orders)
        if self.sketch is None or k == self.sketch.shape[-1]:
            grown = np.empty((self.W, len(self.picks), 2 * k + 8))
            if self.sketch is not None:
                grown[..., :k] = self.sketch
            self.sketch = grown
        self.sketch[..., k] = [c[self.picks] for c in channels]
        self.sums.append(channels.sum(axis=1, dtype=np.float64))
        self.shape = S.shape
        self.orders.append((channels, np.array(E, np.float64), top.astype(np.float32)))
        self.partial = channels.astype(np.float64) if self.partial is None else self.partial + channels
        self.gamma = None

    def _solve(self, below=None):
        """(gamma (W, k + 1), error estimate (W,)): RRE's weights per wavelength and :meth:`error`'s estimate; where
        the estimate on the sketched texels alone is at least ``below``, that lower bound in its place."""
        k1 = len(self.orders)
        gamma, error = np.zeros((self.W, k1)), np.zeros(self.W)
        for w in range(self.W):
            total = self.partial[w]
            if not total.max() > 0.0:               # nothing scatters at this wavelength: the sum is the partial sum
                gamma[w, -1] = 1.0
                continue
            floor = FLOOR * total.max()
            U = self.sketch[w, :, :k1] / np.maximum(total[self.picks], floor)[:, None]
            y = np.linalg.lstsq(U.T @ U, np.ones(k1), rcond=1e-15)[0]
            gamma[w] = g = y / y.sum() if y.sum() != 0.0 else np.eye(k1)[-1]
            last, before = self.sums[-1][w], self.sums[-2][w] if k1 > 1 else 0.0
            q = min(last / before, Q_MAX) if before > 0.0 else 0.0
            per_residual = 1.0 / (1.0 - max(q, 0.0))
            error[w] = np.abs(U @ g).max() * per_residual
            if below is not None and error[w] >= below:
                continue
            residual = np.zeros_like(total)
            for gj, (channels, _, _) in zip(g, self.orders):
                residual += gj * channels[w]
            error[w] = np.abs(residual / np.maximum(total, floor)).max() * per_residual
        return gamma, error

    def error(self, below=None):
        """(W,) the estimated largest relative error of :meth:`sum`'s S per wavelength, max |r| / (1 - q) over
        every texel; where the sketched texels alone give ``below`` or more, that lower bound (cheaper)."""
        self.gamma, error = self._solve(below)
        return error

    def sum(self):
        """(S, E, top): every order's sum, s_k = sum_j gamma_j T_j per wavelength, at least 0."""
        if self.gamma is None:
            self.gamma = self._solve()[0]
        # sum_j gamma_j T_j = sum_i x_i c_i with c_i = sum_{j >= i} gamma_j
        c = np.cumsum(self.gamma[:, ::-1], axis=1)[:, ::-1]                # (W, k + 1)
        c2 = np.concatenate([c, c])                                         # both halves of top
        channels = np.zeros(self.orders[0][0].shape)
        E, top = (np.zeros(part.shape) for part in self.orders[0][1:])
        for i, (x, e, t) in enumerate(self.orders):
            channels += x * c[:, i, None]
            E += e * c[:, i]
            top += t * c2[:, i]
        n = channels.shape[1] // 2
        S = np.concatenate([channels[:, :n].T, channels[:, n:].T], 1).reshape(self.shape)
        return tuple(np.maximum(o, 0.0) for o in (S, E, top))
