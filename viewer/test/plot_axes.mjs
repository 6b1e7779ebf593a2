// The plot panel's axes (viewer/js/plot_axes.js) without a browser: for the column
// (values 0 .. 1.2626e-06, whose lower label the old panel clipped to "00001263") and ranges
// of other magnitudes, the ticks are multiples of 1, 2 or 5 times a power of ten inside the
// range, their labels read back as the tick values (to a tenth of a step), and are short; the
// units follow the column names.
import { axisName, niceTicks, tickLabel, unitOf } from '../js/plot_axes.js';

let failures = 0;
const check = (ok, what) => { if (!ok) failures++; console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`); };

for (const [lo, hi] of [[0, 1.2626e-06], [-5.494e-7, 3.0483e-6], [89.16913692, 89.16913793], [0, 15], [-0.99999, 0.99999],
                        [1.6925e-17, 14.99999], [-2.5e5, 7.1e5], [0.044665, 0.05]]) {
  const { ticks, step } = niceTicks(lo, hi, 5);
  const mantissa = step / 10 ** Math.floor(Math.log10(step) + 1e-12);
  const labels = ticks.map((v) => tickLabel(v, step));
  const misread = ticks.filter((v, k) => !(Math.abs(Number(labels[k]) - v) <= 0.1 * step));
  check(ticks.length >= 2 && ticks.length <= 11 && ticks.every((v) => v >= lo - 1e-9 * step && v <= hi + 1e-9 * step) &&
        [1, 2, 5].some((m) => Math.abs(mantissa - m) < 1e-9) && misread.length === 0 && labels.every((l) => l.length <= 11),
        `[${lo}, ${hi}]: step ${step}, labels ${labels.join(' ')}`);
}
check(unitOf('t') === 's' && unitOf('crank.angle') === 'rad' && unitOf('coupler.omega') === 'rad/s' &&
      unitOf('top.wz') === 'rad/s' && unitOf('l0.vx') === 'm/s' && unitOf('O.fx') === 'N' && unitOf('O.tz') === 'N m' &&
      unitOf('kinetic_energy') === 'J' && unitOf('top.e0') === '' && axisName('l0.x') === 'l0.x [m]' &&
      axisName('constraint_position_violation') === 'constraint_position_violation',
      'units from column names: t [s], .angle [rad], .omega/.w* [rad/s], .v* [m/s], .f* [N], .t* [N m], energies [J]');
process.exit(failures ? 1 : 0);
