#include <stdlib.h>
#include <omp.h>
#include "transport/vpl.h"
#include <stdio.h>
#include <string.h>
#include "render_test_util.h"
#include "transport/pt.h"
#include "transport/vrl.h"
#include "transport_test_util.h"
#include "volume_test_grid.h"
static int LP=48,PS=2,SPP=2; static const vbl_estimator* EST=&vbl_estimator_vrl;
static void run(vbl_scene* s, const char* tag){
  tt_stats a,b; vbl_render_options o=tt_options(2,8,0,1); tt_replicate(s,&vbl_estimator_pt,&o,4,4,&a);
  o=tt_options(PS,SPP,LP,2); double t0=omp_get_wtime(); tt_replicate(s,EST,&o,4,4,&b); printf("time %.2f\n", omp_get_wtime()-t0); double iz; tt_compare(&a,&b,1.0,&iz,tag);}
int main(int argc, char** argv){
  if(argc>2) LP=atoi(argv[2]); if(argc>3) PS=atoi(argv[3]); if(argc>4) SPP=atoi(argv[4]); if(argc>5 && argv[5][0]=='p') EST=&vbl_estimator_vpl;
  int mode = argc>1? atoi(argv[1]):0;
  vbl_camera cam = rt_camera(vbl_v3(0.3, -4.0, 0.5), vbl_v3(0.2, 0, 0), 40.0, 8, 8);
  vbl_scene* s = tt_scene(&cam);
  vbl_volume* box = rt_make_box(9, 0.25, vbl_v3(-1, -1, -1));
  vbl_volume* sph = tt_make_sphere(16, 0.8);
  vbl_affine place = {{{1, 0, 0, 0.7}, {0, 1, 0, 0.2}, {0, 0, 1, 0.3}}};
  if (mode&1) vbl_scene_add_medium(s, box, 0.7, vbl_v3(0.9, 0.6, 0.5), (mode&8)?0.5:0.0, NULL);
  if (mode&2) vbl_scene_add_medium(s, sph, 2.5, vbl_v3(0.5, 0.8, 0.9), (mode&8)?-0.3:0.0, (mode&16)?&place:NULL);
  if (mode&4) tt_add_distant(s, vbl_v3(0.4, 0.6, -0.7), 2.0); else tt_add_point(s, vbl_v3(0.4,0.3,1.6), 10.0);
  run(s, argv[1]);
  return 0;}
