# The CT of BMDockCTReader.xml: an 8-bit display window as a lung-screening export holds it,
# written as ASCII VTK XML image data. 80 x 60 x 36 points of 0.5 mm from (10, 20, 30) mm: a
# 20 x 20 x 10 mm block (x 15-35, y 25-45, z 35-45 mm) and, 1.5 mm beside it, a sphere of radius
# 5 mm at (42, 35, 40) mm. Values 220 in bone, 40 elsewhere. Args: -DOUT=<file.vti>.
set(values "")
foreach(k RANGE 35)
  math(EXPR z2 "60 + ${k}")           # z in half mm: 30 mm + k * 0.5 mm
  foreach(j RANGE 59)
    math(EXPR y2 "40 + ${j}")
    set(row "")
    foreach(i RANGE 79)
      math(EXPR x2 "20 + ${i}")
      set(v 40)
      if(x2 GREATER_EQUAL 30 AND x2 LESS 70 AND y2 GREATER_EQUAL 50 AND y2 LESS 90 AND
         z2 GREATER_EQUAL 70 AND z2 LESS 90)
        set(v 220)
      endif()
      math(EXPR r2 "(${x2} - 84) * (${x2} - 84) + (${y2} - 70) * (${y2} - 70) + (${z2} - 80) * (${z2} - 80)")
      if(r2 LESS 100)                 # (5 mm = 10 half mm)^2
        set(v 220)
      endif()
      string(APPEND row " ${v}")
    endforeach()
    string(APPEND values "${row}\n")
  endforeach()
endforeach()
file(WRITE "${OUT}" "<?xml version=\"1.0\"?>
<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">
  <ImageData WholeExtent=\"0 79 0 59 0 35\" Origin=\"10 20 30\" Spacing=\"0.5 0.5 0.5\">
    <Piece Extent=\"0 79 0 59 0 35\">
      <PointData Scalars=\"ct\">
        <DataArray type=\"UInt8\" Name=\"ct\" format=\"ascii\">
${values}        </DataArray>
      </PointData>
    </Piece>
  </ImageData>
</VTKFile>
")
