import json, math, sys
cam=[0,-8,2.2]
lights=[]
# a ring of eight directional lights behind and around the spheres, ~115 deg from the view
# direction: their mirror reflections sit on each sphere's rim near the Brewster angle, so the
# reflected light is strongly polarized and its AoLP turns with the light's azimuth
for k in range(12):
    a=2*math.pi*k/12
    # in the camera's frame: view axis ~ +y; ring around it
    d=[0.9*math.cos(a), 0.42, 0.9*math.sin(a)+0.15]
    n=math.sqrt(sum(x*x for x in d)); d=[round(x/n,4) for x in d]
    lights.append({"type":"directional","direction":d,"irradiance_w_m2":250})
# a linearly polarized light from beside the camera (metals keep it: DoLP near 1)
lights.append({"type":"directional","direction":[0.35,-0.85,0.4],"irradiance_w_m2":150,
               "polarization":{"linear_deg":30}})
objs=[]
sph=[([-2.2,0.5,0.0],0.9,"plastic_black"),([-0.1,0.0,0.0],0.85,"plastic_white"),([1.9,0.6,0.0],0.9,"metal"),
     ([-1.2,-1.2,-0.55],0.42,"glass"),([0.9,-1.4,-0.6],0.38,"gold"),([2.6,-1.5,-0.62],0.36,"plastic_black")]
for c,r,m in sph:
    objs.append({"type":"sphere","center":c,"radius":r,"material":m})

scene={
 "polarcam_scene":1,
 "name":"stress: glossy dielectric and metal spheres, DoLP up to ~1 at every AoLP",
 "camera":{"position":cam,"look_at":[0.1,0,-0.2],"focal_length_mm":12,"f_number":4},
 "lights":lights,
 "materials":{
   
   "plastic_black":{"n":1.55,"sigma":0.3,"diffuse":"none"},
   "plastic_white":{"n":1.5,"sigma":0.1},
   "glass":{"n":1.5,"sigma":0.03,"diffuse":"none"},
   "metal":{"n":1.2,"k":7.0,"sigma":0.1},
   "gold":{"n":0.3,"k":2.9,"sigma":0.2}},
 "objects":objs,
 "effects":{"diffuse":True,"shadowing":True,"cast_shadows":True,"supersampling":3},
 "sensor":{"preset":"ideal","resolution":[512,384],"pixel_pitch_um":16,"exposure_us":float(sys.argv[1])}
}
s=json.dumps(scene)
for k in ('{"type"','"camera"','"lights"','"materials"','"effects"','"sensor"'):
    s=s.replace(k,'\n '+k)
for k in ('"plastic_black":','"plastic_white":','"glass":','"metal":','"gold":'):
    s=s.replace(k,'\n    '+k)
print(s)
