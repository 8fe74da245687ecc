import json, math, sys
mats = ["bright","dark","gloss_dark","metal","paint","dark",
        "dark","bright","black","paint","gloss_white","bright",
        "bright","gloss_dark","gold","dark","black","metal",
        "black","paint","dark","gloss_white","bright","dark"]
objs=[{"type":"plane","point":[0,0,0],"normal":[0,0,1],"material":"backdrop"}]
tile, gap = 0.18, 0.03
cam=[0,-3.4,9.4]
centres={}
for r in range(4):
    for c in range(6):
        x=(c-2.5)*(tile+gap); y=(1.5-r)*(tile+gap)
        centres[(r,c)]=(x,y)
        m=mats[r*6+c]
        # dark tiles lean 7 degrees (black ones 12) away from the camera: the glint lights' mirror geometry
        # misses them by far more than their gloss (sigma 0.04), so they stay dark
        nrm=[0,0.2079,0.9781] if m=="black" else [0,0.1219,0.9925] if m=="dark" else [0,0,1]
        objs.append({"type":"plane","point":[round(x,4),round(y,4),0.012 if m in ("dark","black") else 0.002],"normal":nrm,
                     "size":[tile,tile],"u_axis":[1,0,0],"material":mats[r*6+c]})
lights=[{"type":"directional","direction":[0.3,-0.5,0.81],"irradiance_w_m2":300}]
# point lights placed so that their mirror glints fall inside three glossy tiles (off centre)
for (r,c),(ox,oy) in (((0,2),(0.03,0.02)),((2,1),(-0.04,0.03)),((3,3),(0.0,-0.03))):
    px,py=centres[(r,c)]; px+=ox; py+=oy
    v=[cam[0]-px,cam[1]-py,cam[2]-0.002]
    s=2.5/v[2]
    lights.append({"type":"point","position":[round(px-s*v[0],4),round(py-s*v[1],4),2.5],"intensity_w_sr":400})
scene={
 "polarcam_scene":1,
 "name":"stress: chart of dark, bright, glossy and metal patches with saturated glints",
 "camera":{"position":cam,"look_at":[0,0,0],"up":[0,1,0],"focal_length_mm":12,"f_number":4},
 "lights":lights,
 "materials":{
   "backdrop":{"n":1.5,"sigma":0.6},
   "bright":{"n":1.46,"k":1.28,"sigma":0.5},
   "paint":{"n":1.47,"k":0.47,"sigma":0.3},
   "dark":{"n":1.5,"sigma":0.04,"diffuse":"none"},
   "black":{"n":1.5,"k":0.3,"sigma":0.04,"diffuse":"none"},
   "gloss_dark":{"n":1.5,"sigma":0.03,"diffuse":"none"},
   "gloss_white":{"n":1.5,"k":0.6,"sigma":0.04},
   "metal":{"n":1.2,"k":7.0,"sigma":0.15},
   "gold":{"n":0.3,"k":2.9,"sigma":0.25}},
 "objects":objs,
 "effects":{"diffuse":True,"shadowing":True,"cast_shadows":True,"supersampling":3},
 "sensor":{"preset":"ideal","resolution":[512,384],"exposure_us":float(sys.argv[1]) if len(sys.argv)>1 else 700}
}
s=json.dumps(scene)
for k in ('{"type"','"camera"','"lights"','"materials"','"effects"','"sensor"','"backdrop"','"bright"','"paint"','"dark"','"black"','"gloss_dark"','"gloss_white"','"metal"','"gold"'):
    s=s.replace(k,'\n    '+k) if k.startswith('{') or k in('"backdrop"','"bright"','"paint"','"dark"','"black"','"gloss_dark"','"gloss_white"','"metal"','"gold"') else s.replace(k,'\n '+k)
print(s)
