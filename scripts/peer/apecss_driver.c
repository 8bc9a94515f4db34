/* A driver for the APECSS library (https://github.com/polycfd/apecss), written for
 * scripts/peer_apecss.sh: it is magbubble's code, not APECSS's, and is compiled against an
 * APECSS checkout that the user supplies (nothing of APECSS is in this repository).
 *
 * It runs one bubble with the options file given, under magbubble's drive convention
 * p_inf(t) = p0 (1 + eps cos(2 pi f t)) (APECSS's own examples use p0 - dp sin(2 pi f t)),
 * from R(0) = r_init at rest, and prints "t R" every `dt_out` seconds to stdout.
 *
 * usage: apecss_driver OPTIONS_FILE T_END F_HZ EPS R_INIT DT_OUT
 */
#include "apecss.h"

static APECSS_FLOAT drive_eps = 0.0;
static APECSS_FLOAT drive_omega = 0.0;

static APECSS_FLOAT p_inf_cos(APECSS_FLOAT t, struct APECSS_Bubble *Bubble)
{
  return Bubble->p0 * (1.0 + drive_eps * APECSS_COS(drive_omega * t));
}

static APECSS_FLOAT p_inf_cos_dt(APECSS_FLOAT t, struct APECSS_Bubble *Bubble)
{
  return -Bubble->p0 * drive_eps * drive_omega * APECSS_SIN(drive_omega * t);
}

int main(int argc, char **args)
{
  if (argc != 7)
  {
    fprintf(stderr, "usage: %s OPTIONS_FILE T_END F_HZ EPS R_INIT DT_OUT\n", args[0]);
    return 2;
  }
  char options[APECSS_STRINGLENGTH];
  snprintf(options, sizeof options, "%s", args[1]);
  double t_end = atof(args[2]), f = atof(args[3]), eps = atof(args[4]), r_init = atof(args[5]), dt_out = atof(args[6]);
  drive_eps = eps;
  drive_omega = 2.0 * APECSS_PI * f;

  struct APECSS_Bubble *Bubble = malloc(sizeof(struct APECSS_Bubble));
  apecss_bubble_initializestruct(Bubble);
  apecss_bubble_setdefaultoptions(Bubble);
  apecss_bubble_readoptions(Bubble, options);

  struct APECSS_Gas *Gas = malloc(sizeof(struct APECSS_Gas));
  struct APECSS_Liquid *Liquid = malloc(sizeof(struct APECSS_Liquid));
  struct APECSS_Interface *Interface = malloc(sizeof(struct APECSS_Interface));
  struct APECSS_NumericsODE *NumericsODE = malloc(sizeof(struct APECSS_NumericsODE));
  apecss_gas_setdefaultoptions(Gas);
  apecss_liquid_setdefaultoptions(Liquid);
  apecss_interface_setdefaultoptions(Interface);
  apecss_odesolver_setdefaultoptions(NumericsODE);
  apecss_gas_readoptions(Gas, options);
  apecss_liquid_readoptions(Liquid, options);
  apecss_interface_readoptions(Interface, options);
  apecss_odesolver_readoptions(NumericsODE, options);
  Bubble->Gas = Gas;
  Bubble->Liquid = Liquid;
  Bubble->Interface = Interface;
  Bubble->NumericsODE = NumericsODE;

  Bubble->tStart = 0.0;
  Bubble->tEnd = t_end;
  Bubble->dt = APECSS_MIN(1.0e-11, t_end);

  /* A sine excitation so that APECSS wires its excitation hooks; replaced by the cosine below. */
  struct APECSS_Excitation *Excitation = malloc(sizeof(struct APECSS_Excitation));
  Excitation->type = APECSS_EXCITATION_SIN;
  Excitation->f = f;
  Excitation->dp = 0.0;
  Bubble->Excitation = Excitation;

  apecss_gas_processoptions(Gas);
  apecss_liquid_processoptions(Liquid);
  apecss_interface_processoptions(Interface);
  apecss_odesolver_processoptions(NumericsODE);
  apecss_bubble_processoptions(Bubble);
  Bubble->get_pressure_infinity = p_inf_cos;
  Bubble->get_pressurederivative_infinity = p_inf_cos_dt;
  Bubble->progress_initial = apecss_bubble_solver_progress_initialnone;
  Bubble->progress_update = apecss_bubble_solver_progress_updatenone;
  Bubble->progress_final = apecss_bubble_solver_progress_finalnone;

  apecss_bubble_initialize(Bubble);
  Bubble->R = r_init; /* start away from R0 (a ring-down) when asked: pG0 stays the one at R0 */
  Bubble->ODEsSol[1] = r_init;

  apecss_bubble_solver_initialize(Bubble);
  printf("%.17e %.17e\n", 0.0, (double) Bubble->R);
  long n = (long) (t_end / dt_out + 0.5);
  for (long i = 1; i <= n; i++)
  {
    apecss_bubble_solver_run(i * dt_out, Bubble);
    printf("%.17e %.17e\n", (double) Bubble->t, (double) Bubble->R);
  }
  apecss_bubble_solver_finalize(Bubble);
  fprintf(stderr, "apecss: %d steps, %d sub-iterations, pG0 = %.10e Pa\n", Bubble->dtNumber, Bubble->nSubIter, (double) Bubble->pG0);
  return 0;
}
