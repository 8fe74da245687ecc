import json, sys
which=sys.argv[1]
cfg={
 "star":("Siemens star: bright matte wedges on glossy polarizing black, every orientation and frequency","star.obj","paint","gloss_black"),
 "gratings":("bar gratings at 8 orientations, ~3 and ~5 px periods: metal bars on glossy polarizing black","gratings.obj","metal","gloss_black"),
 "text":("text-like 5x7 glyph lines, strokes of 1-3.5 px: glossy black ink (strongly polarized) on matte paper","text.obj","gloss_black","paper"),
}[which]
scene={
 "polarcam_scene":1,
 "name":"stress: "+cfg[0],
 "camera":{"position":[0,-6.2,6.8],"look_at":[0,-0.02,0],"up":[0,1,0],"focal_length_mm":12,"f_number":4},
 "lights":[{"type":"directional","direction":[0.1,0.62,0.78],"irradiance_w_m2":150 if which=="text" else 300},
           {"type":"directional","direction":[-0.5,-0.3,0.81],"irradiance_w_m2":200 if which=="text" else 60}],
 "materials":{
   "paper":{"n":1.46,"k":1.28,"sigma":0.6},
   "paint":{"n":1.46,"k":1.28,"sigma":0.5},
   "gloss_black":{"n":1.55,"sigma":0.18,"diffuse":"none"},
   "metal":{"n":1.2,"k":7.0,"sigma":0.25}},
 "objects":[{"type":"plane","point":[0,0,0],"normal":[0,0,1],"material":cfg[3]},
            {"type":"mesh","file":cfg[1],"position":[0,0,0.001],"scale":1.5 if which=="star" else 1,"material":cfg[2],"smooth":False}],
 "effects":{"diffuse":True,"shadowing":True,"cast_shadows":True,"supersampling":3},
 "sensor":{"preset":"ideal","resolution":[512,384],"exposure_us":float(sys.argv[2])}
}
s=json.dumps(scene)
for k in ('{"type"','"camera"','"lights"','"materials"','"effects"','"sensor"'):
    s=s.replace(k,'\n '+k)
print(s)
