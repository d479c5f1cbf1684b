!> Case reader, the messages: every class of input error (unknown key, bad value, bad body,
!> time, section, document, strength, softening, material keys, Newtonian fluid) gives one
!> message (code exit_input) that names the key path, the bad value and what is allowed.
!> The values of valid cases are tested in test_mpm_case.
program test_mpm_case_errors
    use mpm_kinds, only: wp, i8
    use mpm_error, only: exit_input
    use mpm_case, only: case_type
    use mpm_case_stability, only: critical_time_step, p_wave_speed
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_testing_case, only: domain_2d, materials_1, materials_2, bodies_1, time_1, tol, &
        elastic_part, case_text, soil_case, read_valid, expect_error, write_text, delete_file
    implicit none

    character(len=*), parameter :: state_file = "test_mpm_case_errors_state.tmp"
    character(len=*), parameter :: rigid_materials = '"materials": [{"name": "soil", "type": ' &
        //'"linear_elastic", "E": 1e6, "nu": 0.0, "rho": 1000}, {"name": "steel", "type": ' &
        //'"rigid", "rho": 7800}]'
        !! a soil and a rigid material
    character(len=*), parameter :: rigid_bodies = '"bodies": [{"material": "soil", "min": ' &
        //'[0, 0], "max": [0.2, 0.1]}, {"material": "steel", "min": [0.3, 0], "max": [0.4, 0.1]}]'
        !! a soil block and a rigid block beside it
        !! a file whose existence load_state checks (its own name: the suites may run side by
        !! side in one folder)

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_case_errors")
    call write_text(state_file, "not a real state file: only its existence is checked")
    call test_key_errors()
    call test_value_errors()
    call test_body_errors()
    call test_stl_body_errors()
    call test_polygon_body_errors()
    call test_shape_bodies()
    call test_time_errors()
    call test_section_errors()
    call test_document_errors()
    call test_strength_errors()
    call test_softening_errors()
    call test_material_key_errors()
    call test_newtonian_errors()
    call delete_file(state_file)
    call finish(suite)

contains

    subroutine test_key_errors()
        call expect_error(suite, case_text(extra='"nmae": "x"'), &
            [character(len=200) :: "unknown key 'nmae'", "did you mean 'name'?"], &
            "unknown top-level key")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"xmn": "fixed"}}'), [character(len=200) :: &
            "unknown key 'domain.boundaries.xmn'", "did you mean 'xmin'?"], "nested unknown key")
        call expect_error(suite, case_text(extra='"completely_unrelated": 1'), [character(len=200) :: &
            "unknown key 'completely_unrelated'", "the keys allowed in the top level are:", &
            "domain, particles, materials"], "unknown key far from any key")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "e": 1e6, "nu": 0, "rho": 1000}]'), [character(len=200) :: &
            "unknown key 'materials[1].e'", "did you mean 'E'? (keys are case-sensitive)"], &
            "key in the wrong case")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"dx": 0.2}'), [character(len=200) :: "duplicate key 'domain.dx'"], "duplicate key")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": "0.1"}'), &
            [character(len=200) :: "domain.dx has the wrong type", "expected a number > 0 [m]", &
            'found a string ("0.1")'], "wrong type")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2}'), &
            [character(len=200) :: "missing required key 'domain.dx' (a number > 0 [m])"], &
            "missing required key")
        call expect_error(suite, case_text(time='"time": {}'), &
            [character(len=200) :: "missing required key 'time.tend'"], "missing tend")
    end subroutine test_key_errors

    subroutine test_value_errors()
        type(case_type) :: case

        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 0, "nu": 0, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].E = 0 is out of range: must be > 0 [Pa]"], "E = 0")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": -5e6, "nu": 0, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].E = -5000000 is out of range: must be > 0 [Pa]"], "E < 0")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 1e6, "nu": 0.5, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].nu = 0.5 is out of range: must be >= 0 and < 0.5"], "nu = 0.5")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 1e6, "nu": -0.1, "rho": 1000}]'), [character(len=200) :: &
            "materials[1].nu = -0.1 is out of range: must be >= 0 and < 0.5"], "nu < 0")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"elastic", "E": 1e6, "nu": 0.2, "rho": 0}]'), [character(len=200) :: &
            "materials[1].rho = 0 is out of range: must be > 0 [kg/m3]"], "rho = 0")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"plastic", "E": 1e6, "nu": 0.2, "rho": 1}]'), [character(len=200) :: &
            'materials[1].type = "plastic" is not allowed', '"linear_elastic", "elastic"'], &
            "unknown material type")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": -0.1}'), &
            [character(len=200) :: &
            "inputs/bad.json: domain.dx = -0.1 is out of range: must be > 0 [m]"], "dx < 0", &
            source="inputs/bad.json")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0}'), &
            [character(len=200) :: "domain.dx = 0 is out of range: must be > 0 [m]"], "dx = 0")
        call expect_error(suite, case_text(domain='"domain": {"nx": 2.5, "ny": 2, "dx": 0.1}'), &
            [character(len=200) :: "domain.nx = 2.5 is not a whole number"], "nx = 2.5")
        call expect_error(suite, case_text(domain='"domain": {"nx": 100000, "ny": 100000, "dx": 1}'), &
            [character(len=200) :: "100000 x 100000 cells", "nodes, more than the 2147483647"], &
            "too many nodes")
        call expect_error(suite, case_text(extra='"particles": {"ppc": 0}'), [character(len=200) :: &
            "particles.ppc = 0 is out of range: must be an integer >= 1 and <= 10"], "ppc = 0")
        call expect_error(suite, case_text(extra='"particles": {"ppc": 1.5}'), [character(len=200) :: &
            "particles.ppc = 1.5 is not a whole number: must be an integer >= 1 and <= 10"], &
            "ppc = 1.5")
        call read_valid(suite, case_text(extra='"particles": {"ppc": 3.0}'), case, "ppc = 3.0")
        call check(suite, case%particles%ppc == 3, "ppc = 3.0 is the integer 3")
        call expect_error(suite, case_text(extra='"particles": {"seed": 3}'), [character(len=200) :: &
            "particles.seed only applies to particles.distribution"], "seed without random")
        call expect_error(suite, case_text(extra='"name": "my case"'), [character(len=200) :: &
            'name = "my case" is not allowed', "letters, digits"], "name with a blank")
        call expect_error(suite, case_text(extra='"gravity": [0, -9.81, 0]'), [character(len=200) :: &
            "gravity must have 2 numbers", "found 3"], "gravity of the wrong length")
        call expect_error(suite, case_text(extra='"gravity": [0, "down"]'), [character(len=200) :: &
            "gravity[2] has the wrong type: expected a number"], "gravity item type")
        call expect_error(suite, case_text(extra='"solver": {"scheme": "RK4"}'), [character(len=200) :: &
            'solver.scheme = "RK4" is not allowed', '"USF", "USL", "MUSL"'], "unknown scheme")
        call expect_error(suite, case_text(extra='"output": {"fields": ["velocity", "pressure"]}'), &
            [character(len=200) :: 'output.fields[2] = "pressure" is not a field', &
            '"position", "displacement"'], "unknown output field")
        call expect_error(suite, case_text(extra='"output": {"fields": ["mass", "mass"]}'), &
            [character(len=200) :: 'output.fields[2] = "mass" is listed twice'], "field twice")
        call expect_error(suite, case_text(extra='"output": {"grid": 1}'), [character(len=200) :: &
            "output.grid has the wrong type: expected true or false, found a number (1)"], &
            "boolean expected")
        call expect_error(suite, case_text(extra='"save_state": ""'), [character(len=200) :: &
            'save_state = "" is not allowed: must be a non-empty string'], "empty save_state")
    end subroutine test_value_errors

    subroutine test_body_errors()
        type(case_type) :: case

        call expect_error(suite, case_text(bodies='"bodies": [{"name": "block", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.5, 0.1]}]'), [character(len=200) :: 'bodies[1] "block"', &
            "corner max = (0.5, 0.1)", "outside the domain [0, 0.4] x [0, 0.2] [m]"], &
            "body outside the domain")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"min": [0, -0.1], "max": [0.1, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "body1": corner min = (0, -0.1)'], "body below the domain")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.2, 0.1]}, {"name": "b", "material": "soil", ' &
            //'"min": [0.1, 0.05], "max": [0.3, 0.2]}]'), [character(len=200) :: &
            'bodies[2] "b" overlaps bodies[1] "a"', "[0.1, 0.3] x [0.05, 0.2]"], &
            "overlapping bodies")
        call read_valid(suite, case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.2, 0.1]}, {"name": "b", "material": "soil", ' &
            //'"min": [0.2, 0], "max": [0.4, 0.3e-0]}]', &
            domain='"domain": {"nx": 4, "ny": 3, "dx": 0.1}'), case, &
            "bodies that touch do not overlap")
        call expect_error(suite, case_text(materials=materials_2, bodies='"bodies": [{"name": "a", ' &
            //'"material": "sand", "min": [0, 0], "max": [0.2, 0.1]}]'), [character(len=200) :: &
            'bodies[1].material = "sand" is not a material', '"soil", "rock"'], &
            "unknown material name")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "thin", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.02, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "thin": the box [0, 0.02] x [0, 0.1] [m] holds no particle'], &
            "body without particles")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "flat", "material": "soil", ' &
            //'"min": [0, 0.1], "max": [0.2, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "flat": min[2] = 0.1 must be below max[2] = 0.1'], "empty box")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.1, 0.1]}, {"name": "a", "material": "soil", ' &
            //'"min": [0.2, 0], "max": [0.3, 0.1]}]'), [character(len=200) :: &
            'bodies[2].name = "a" is already the name of bodies[1]'], "body names unique")
        call expect_error(suite, case_text(materials='"materials": [{"name": "x", "type": ' &
            //'"elastic", "E": 1, "nu": 0, "rho": 1}, {"name": "x", "type": "elastic", ' &
            //'"E": 1, "nu": 0, "rho": 1}]'), [character(len=200) :: &
            'materials[2].name = "x" is already the name of materials[1]'], &
            "material names unique")
        call expect_error(suite, case_text(materials='"materials": []'), [character(len=200) :: &
            "materials is an empty array"], "no material")
        call expect_error(suite, case_text(bodies=""), [character(len=200) :: &
            "missing required key 'bodies'", "load_state"], "no bodies and no load_state")
        call expect_error(suite, case_text(extra='"load_state": "no/such/state.h5"'), &
            [character(len=200) :: "load_state: file 'no/such/state.h5' not found"], &
            "missing load_state file")
        call expect_error(suite, case_text(extra='"load_state": "'//state_file//'"'), &
            [character(len=200) :: "bodies cannot be given together with load_state", &
            "the particles come from the state file"], "bodies with load_state")
    end subroutine test_body_errors

    !> Bodies from closed STL surfaces (tests/data/stl): a valid one and every refusal.
    subroutine test_stl_body_errors()
        type(case_type) :: case
        character(len=*), parameter :: cube = '"file": "tests/data/stl/unit_cube.stl"'

        call read_valid(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //cube//', "scale": 0.1, "offset": [0.1, 0.05, -0.05]}]'), case, "STL body valid")
        call check(suite, allocated(case%bodies(1)%triangle), "STL body keeps its triangles")
        if (allocated(case%bodies(1)%triangle)) then
            call check(suite, size(case%bodies(1)%triangle, 3) == 12, "STL body: 12 triangles")
            call check_close(suite, case%bodies(1)%xmax(1), 0.2_wp, tol, &
                "STL body: max = bounding box of x*scale + offset")
        end if
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //cube//', "min": [0, 0], "max": [0.1, 0.1]}]'), [character(len=200) :: &
            'bodies[1] "s"', "give one of 'file' (a closed STL surface), 'min' and 'max' " &
            //"(a box), 'polygon', 'circle', 'sphere' or 'cylinder', not several"], &
            "STL body with min and max")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil"}]'), &
            [character(len=200) :: 'bodies[1] "s"', "give one of 'min' and 'max' (a box), " &
            //"'polygon' or 'circle' (2D), 'sphere' or 'cylinder' (3D), 'file'", &
            "none was given"], "body with neither file nor min/max")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.1, 0.1], "scale": 2}]'), [character(len=200) :: &
            "bodies[1].scale only applies to a body given by 'file'"], "scale of a box")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //'"file": "tests/data/stl/open_cube.stl", "scale": 0.1, ' &
            //'"offset": [0, 0, -0.05]}]'), [character(len=200) :: &
            'bodies[1] "s": the surface ''tests/data/stl/open_cube.stl'' is not closed', &
            "a body needs a closed surface"], "open STL surface")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //'"file": "tests/data/stl/prism.stl"}]'), [character(len=200) :: &
            'bodies[1] "s": the bounding box of the surface', &
            "surface 'tests/data/stl/prism.stl', corner max = (0.69", &
            "outside the domain [0, 0.4] x [0, 0.2] [m]"], "STL body outside the domain")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //'"file": "no/such.stl"}]'), [character(len=200) :: &
            "bodies[1].file: STL file 'no/such.stl' not found"], "missing STL file")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //cube//', "scale": 0.02, "offset": [0.1, 0.1, -0.01]}]'), [character(len=200) :: &
            'bodies[1] "s": the closed surface', "holds no particle"], "STL body too thin")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "s", "material": "soil", ' &
            //cube//', "scale": 0.1, "offset": [0, 0, 0.05]}]'), [character(len=200) :: &
            'bodies[1] "s"', "section by the plane z = 0"], "2D STL body off z = 0")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"min": [0, 0], "max": [0.15, 0.1]}, {"name": "s", "material": "soil", ' &
            //cube//', "scale": 0.1, "offset": [0.1, 0, -0.05]}]'), [character(len=200) :: &
            'bodies[2] "s" overlaps bodies[1] "a"'], "STL bounding box overlaps a box")
    end subroutine test_stl_body_errors

    subroutine test_polygon_body_errors()
        type(case_type) :: case
        character(len=*), parameter :: lower = '{"name": "lower", "material": "soil", ' &
            //'"polygon": [[0, 0], [0.4, 0], [0.4, 0.2]]}'
        character(len=*), parameter :: upper = '{"name": "upper", "material": "soil", ' &
            //'"polygon": [[0, 0], [0.4, 0.2], [0, 0.2]]}'

        ! two triangles that split the domain along its diagonal: their bounding boxes are
        ! the same, their particles are not (no particle centre lies on the diagonal)
        call read_valid(suite, case_text(bodies='"bodies": ['//lower//', '//upper//']'), case, &
            "polygons whose bounding boxes meet, bodies that do not")
        if (allocated(case%bodies)) then
            call check(suite, case%bodies(1)%particles + case%bodies(2)%particles == 32 .and. &
                case%bodies(1)%particles == 16, "the two triangles share the 32 particles " &
                //"of the domain, 16 each")
            call check(suite, allocated(case%bodies(2)%polygon) .and. &
                all(case%bodies(2)%xmax(1:2) == [0.4_wp, 0.2_wp]), &
                "a polygon keeps its vertices; min and max are its bounding box")
        end if
        call read_valid(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0], [0.2, 0.1], [0, 0.1]]}]'), case, "a rectangle")
        if (allocated(case%bodies)) call check(suite, case%bodies(1)%particles == 8, &
            "a rectangle holds the particles of the equal box (8)")
        call expect_error(suite, case_text(bodies='"bodies": ['//lower//', {"name": "b", ' &
            //'"material": "soil", "polygon": [[0.1, 0], [0.4, 0], [0.4, 0.2], [0.1, 0.2]]}]'), &
            [character(len=200) :: 'bodies[2] "b" overlaps bodies[1] "lower": 15 particle ' &
            //"sites lie in both"], "overlapping polygons")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0.2], [0.2, 0], [0, 0.2]]}]'), [character(len=200) :: &
            "bodies[1].polygon crosses itself: the edge from vertex 1 (0, 0) meets the edge " &
            //"from vertex 3 (0.2, 0)"], "a bow tie")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0], [0.2, 0], [0, 0.2]]}]'), [character(len=200) :: &
            "bodies[1].polygon: vertex 2 (0.2, 0) is repeated"], "a repeated vertex")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.1, 0], [0.2, 0]]}]'), [character(len=200) :: &
            "bodies[1].polygon crosses itself"], "three vertices on a line")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0]]}]'), [character(len=200) :: &
            "bodies[1].polygon has 2 points; give at least 3, each an array of 2 numbers"], &
            "two vertices")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0, 0], [0.2, 0.1]]}]'), [character(len=200) :: &
            "bodies[1].polygon[2] must have 2 numbers"], "a vertex of three numbers")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0], "a"]}]'), [character(len=200) :: &
            "bodies[1].polygon[3] has the wrong type"], "a vertex that is no array")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.5, 0], [0.2, 0.1]]}]'), [character(len=200) :: &
            "the bounding box of the polygon, corner max = (0.5, 0.1) lies outside the domain"], &
            "a polygon outside the domain")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "p", "material": "soil", ' &
            //'"min": [0, 0], "polygon": [[0, 0], [0.2, 0], [0.2, 0.1]]}]'), &
            [character(len=200) :: "give one of 'polygon', 'min' and 'max' (a box) or " &
            //"'circle', not several"], "a polygon and a box")
        call expect_error(suite, case_text(domain='"dimension": 3, "domain": {"nx": 4, ' &
            //'"ny": 2, "nz": 2, "dx": 0.1}', bodies='"bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [0.2, 0], [0.2, 0.1]]}]'), [character(len=200) :: &
            "bodies[1].polygon: a polygon body is two-dimensional"], "a polygon in 3D")
    end subroutine test_polygon_body_errors

    !> Circles, spheres and cylinders: the particles inside them, and what is refused.
    subroutine test_shape_bodies()
        type(case_type) :: case
        character(len=*), parameter :: domain_3d = '"dimension": 3, "domain": {"nx": 10, ' &
            //'"ny": 10, "nz": 10, "dx": 0.1}'
        integer(i8) :: n
        real(wp) :: expected

        ! a circle of radius 0.3 m, dx 0.01 m, ppc 2: about pi r^2 / h^2 particles
        call read_valid(suite, '{"domain": {"nx": 100, "ny": 100, "dx": 0.01}, '//materials_1 &
            //', "bodies": [{"material": "soil", "circle": {"center": [0.5, 0.5], "radius": ' &
            //'0.3}}], '//time_1//'}', case, "circle body")
        expected = acos(-1.0_wp)*0.3_wp**2/0.005_wp**2
        n = case%bodies(1)%particles
        call check(suite, abs(real(n, wp)/expected - 1.0_wp) < 2.0e-3_wp, "circle: pi r^2 / h^2 " &
            //"particles (0.2 %)")
        call check_close(suite, case%bodies(1)%xmin(1), 0.2_wp, tol, "circle: bounding box")
        ! a sphere of radius 0.4 m in a 1 m cube, dx 0.1, ppc 2: 4/3 pi r^3 / h^3
        call read_valid(suite, '{'//domain_3d//', '//materials_1//', "bodies": [{"material": ' &
            //'"soil", "sphere": {"center": [0.5, 0.5, 0.5], "radius": 0.4}}], '//time_1//'}', &
            case, "sphere body")
        expected = 4.0_wp/3.0_wp*acos(-1.0_wp)*0.4_wp**3/0.05_wp**3
        n = case%bodies(1)%particles
        call check(suite, abs(real(n, wp)/expected - 1.0_wp) < 0.03_wp, "sphere: 4/3 pi r^3 / h^3 " &
            //"particles (3 %: 1072 sites)")
        ! a cylinder along x, radius 0.3, length 0.8, beside a box it does not touch
        call read_valid(suite, '{'//domain_3d//', '//materials_1//', "bodies": [{"material": ' &
            //'"soil", "cylinder": {"start": [0.1, 0.5, 0.5], "end": [0.9, 0.5, 0.5], ' &
            //'"radius": 0.3}}, {"material": "soil", "min": [0, 0, 0], "max": [1, 1, 0.1]}], ' &
            //time_1//'}', case, "cylinder body")
        expected = acos(-1.0_wp)*0.3_wp**2*0.8_wp/0.05_wp**3
        n = case%bodies(1)%particles
        call check(suite, abs(real(n, wp)/expected - 1.0_wp) < 0.03_wp, "cylinder: pi r^2 L / " &
            //"h^3 particles (3 %)")
        call check_close(suite, case%bodies(1)%xmin(2), 0.2_wp, tol, "cylinder: bounding box")
        ! refused
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "sphere": ' &
            //'{"center": [0.2, 0.1], "radius": 0.05}}]'), [character(len=200) :: &
            "bodies[1].sphere: a sphere is a 3D body; in a 2D case give a 'circle'"], "sphere in 2D")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "circle": ' &
            //'{"center": [0.2, 0.1], "radius": 0}}]'), [character(len=200) :: &
            "bodies[1].circle.radius = 0 is out of range: must be > 0 [m]"], "zero radius")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "circle": ' &
            //'{"center": [0.2, 0.1], "radius": 0.15}}]'), [character(len=200) :: &
            "the bounding box of the circle, corner min = (0.05, -0.05) lies outside the domain"], &
            "circle outside the domain")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "circle": ' &
            //'{"center": [0.2, 0.1], "radius": 0.05}, "min": [0, 0]}]'), [character(len=200) :: &
            "give one of 'circle', 'min' and 'max' (a box), 'polygon' or 'file', not several"], &
            "circle and box")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "circle": ' &
            //'{"centre": [0.2, 0.1], "radius": 0.05}}]'), [character(len=200) :: &
            "unknown key 'bodies[1].circle.centre'"], "circle key misspelt")
        call expect_error(suite, case_text(domain=domain_3d, bodies='"bodies": [{"material": ' &
            //'"soil", "cylinder": {"start": [0.5, 0.5, 0.5], "end": [0.5, 0.5, 0.5], ' &
            //'"radius": 0.1}}]'), [character(len=200) :: "bodies[1].cylinder: start and end " &
            //"are the same point"], "cylinder of no length")
        call expect_error(suite, case_text(bodies='"bodies": [{"name": "a", "material": "soil", ' &
            //'"circle": {"center": [0.1, 0.1], "radius": 0.08}}, {"name": "b", "material": ' &
            //'"soil", "circle": {"center": [0.2, 0.1], "radius": 0.08}}]'), [character(len=200) :: &
            'bodies[2] "b" overlaps bodies[1] "a"', "particle sites lie in both"], &
            "overlapping circles")
        ! a layer between two height fields
        call read_valid(suite, '{"domain": {"nx": 40, "ny": 20, "dx": 0.01}, '//materials_1 &
            //', "bodies": [{"material": "soil", "top": "tests/data/stl/layer_top.stl", ' &
            //'"bottom": "tests/data/stl/layer_bottom.stl"}], '//time_1//'}', case, "layer body")
        ! the sites (i + 1/2, j + 1/2) h, h = 5 mm, with x <= 0.375 and 0.0625 + 0.25 x < y <
        ! 0.1875: 1134 (counted site by site; the area / h^2 is 1171.9, the top at a site edge)
        n = case%bodies(1)%particles
        call check(suite, n == 1134_i8, "layer: the 1134 sites between the surfaces")
        call check_close(suite, case%bodies(1)%xmax(1), 0.375_wp, tol, "layer: the surfaces' " &
            //"common extent")
        call check_close(suite, case%bodies(1)%xmin(2), 0.0625_wp, tol, "layer: from the " &
            //"bottom surface's lowest point")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "top": ' &
            //'"tests/data/stl/layer_top.stl"}]'), [character(len=200) :: &
            "missing required key 'bodies[1].bottom'"], "layer without bottom")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "top": ' &
            //'"tests/data/stl/layer_top.stl", "bottom": "tests/data/stl/none.stl"}]'), &
            [character(len=200) :: "bodies[1].bottom: STL file 'tests/data/stl/none.stl' not " &
            //"found"], "layer bottom missing")
        call expect_error(suite, case_text(bodies='"bodies": [{"material": "soil", "top": ' &
            //'"tests/data/stl/layer_top.stl", "bottom": "tests/data/stl/layer_bottom.stl", ' &
            //'"min": [0, 0]}]'), [character(len=200) :: "give one of 'top' and 'bottom' (a " &
            //"layer)"], "layer and box")
    end subroutine test_shape_bodies

    subroutine test_time_errors()
        type(case_type) :: case

        ! critical step dx/c_p = 0.1/31.6227766 = 0.00316228 s (6 digits)
        call expect_error(suite, case_text(time='"time": {"tend": 1, "dt": 0.01}'), &
            [character(len=200) :: "time.dt = 0.01 s is above the critical time step " &
            //"0.00316228 s of this case (dx / max(c_p + |v|)); use a smaller dt or set " &
            //"time.cfl instead"], "dt above the critical step")
        call read_valid(suite, case_text(time='"time": {"tend": 1, "dt": 0.003}'), case, &
            "dt below the critical step")
        call check_close(suite, critical_time_step(case%dim, case%domain%dx, case%materials, &
            case%bodies), 0.1_wp/p_wave_speed(case%materials(1)), 1.0e-15_wp, "critical step of the case")
        call expect_error(suite, case_text(time='"time": {"tend": 1, "dt": 1e-3, "cfl": 0.5}'), &
            [character(len=200) :: "time.dt and time.cfl are alternatives"], "dt and cfl")
        call expect_error(suite, case_text(time='"time": {"tend": 1, "cfl": 1.5}'), &
            [character(len=200) :: "time.cfl = 1.5 is out of range: must be > 0 and <= 1"], &
            "cfl > 1")
        call expect_error(suite, case_text(time='"time": {"tend": 0}'), [character(len=200) :: &
            "time.tend = 0 is out of range: must be > 0 [s]"], "tend = 0")
        call expect_error(suite, case_text(time='"time": {"tend": 1e9}'), [character(len=200) :: &
            "time.tend = 1e9 s needs more than 1e9 steps"], "too many steps")
        ! with load_state the critical step comes from the fastest material: rock has
        ! c_p = sqrt((K + 4G/3)/rho) = sqrt(1.2e9/2500) = 692.82 m/s, dx/c_p = 0.000144338 s
        call expect_error(suite, "{"//domain_2d//", "//materials_2//', "load_state": "' &
            //state_file//'", "time": {"tend": 1, "dt": 2e-4}}', [character(len=200) :: &
            "time.dt = 0.0002 s is above the critical time step 0.000144338 s"], &
            "dt with load_state: fastest material")
    end subroutine test_time_errors

    subroutine test_section_errors()
        character(len=*), parameter :: mc_soil = '"materials": [{"name": "soil", "type": ' &
            //'"mohr_coulomb", '//elastic_part//', "phi": 20, "c": 1000}]'

        call expect_error(suite, case_text(extra='"contact": {"type": "terrain_stl", "mu": 0.4, ' &
            //'"file": "data/no_such_terrain.stl"}'), [character(len=200) :: "contact.file", &
            "data/no_such_terrain.stl' not found"], "terrain_stl: missing STL file")
        call expect_error(suite, case_text(extra='"contact": {"type": "terrain_stl", ' &
            //'"file": "tests/data/stl/floor_2.stl"}'), [character(len=200) :: "contact.mu"], &
            "terrain_stl: mu is required")
        call expect_error(suite, case_text(extra='"contact": {"type": "terrain_stl", "mu": -0.1, ' &
            //'"file": "tests/data/stl/floor_2.stl"}'), [character(len=200) :: "contact.mu"], &
            "terrain_stl: negative mu")
        call expect_error(suite, case_text(extra='"contact": {"type": "terrain_stl", "mu": 0.4, ' &
            //'"file": "tests/data/stl/floor_2.stl", "scale": 0}'), [character(len=200) :: &
            "contact.scale"], "terrain_stl: scale 0")
        call expect_error(suite, case_text(extra='"contact": {"type": "terrain_stl", "mu": 0.4, ' &
            //'"file": "tests/data/stl/floor_2.stl", "offset": [0, 1]}'), &
            [character(len=200) :: "contact.offset must have 3 numbers"], &
            "terrain_stl: offset of 2 numbers")
        call expect_error(suite, case_text(extra='"contact": {"type": "terrain_stl", "mu": 0.4, ' &
            //'"file": "tests/data/stl/floor_2.stl", "normal": [0, 1, 0]}'), &
            [character(len=200) :: "contact.normal"], "terrain_stl: unknown key")
        call expect_error(suite, case_text(extra='"contact": {"type": "none", "mu": 0.4}'), &
            [character(len=200) :: "contact.mu only applies", "terrain_stl"], "mu without STL")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "nz": 2, "dx": 0.1}', &
            extra='"dimension": 2'), [character(len=200) :: &
            "domain.nz is given but dimension = 2"], "nz with dimension 2")
        call expect_error(suite, case_text(extra='"dimension": 3'), [character(len=200) :: &
            "missing required key 'domain.nz'", "dimension = 3"], "dimension 3 without nz")
        call expect_error(suite, case_text(extra='"dimension": 4'), [character(len=200) :: &
            "dimension = 4 is out of range: must be an integer >= 2 and <= 3"], "dimension 4")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"zmin": "fixed"}}'), [character(len=200) :: &
            "domain.boundaries.zmin is not allowed in a 2D case"], "z face in 2D")
        call expect_error(suite, case_text(domain='"domain": {"nx": 4, "ny": 2, "dx": 0.1, ' &
            //'"boundaries": {"xmin": "clamped"}}'), [character(len=200) :: &
            'domain.boundaries.xmin = "clamped" is not allowed', &
            'must be one of "free", "sliding", "fixed"'], "unknown boundary condition")
        call expect_error(suite, case_text(extra='"damping": {"type": "none", "value": 0.1}'), &
            [character(len=200) :: 'damping.value only applies to damping.type = "local"'], &
            "damping value without local")
        call expect_error(suite, case_text(extra='"damping": {"type": "local"}'), &
            [character(len=200) :: "missing required key 'damping.value'"], "local no value")
        call expect_error(suite, case_text(extra='"damping": {"type": "local", "value": 1}'), &
            [character(len=200) :: "damping.value = 1 is out of range: must be >= 0 and < 1"], &
            "damping value 1")
        call expect_error(suite, case_text(extra='"progress": {"interval": 0}'), [character(len=200) :: &
            "progress.interval = 0 is out of range: must be > 0 [s]"], "progress 0")
        call expect_error(suite, case_text(extra='"output": {"interval": -1}'), [character(len=200) :: &
            "output.interval = -1 is out of range: must be >= 0 [s]"], "output interval < 0")
        ! initial_stress
        call expect_error(suite, case_text(extra='"gravity": [0, -9.81], "initial_stress": ' &
            //'{"type": "k0", "k0": 0}'), [character(len=200) :: "initial_stress.k0", &
            "> 0 and < 10"], "k0 of zero")
        call expect_error(suite, case_text(extra='"gravity": [0, -9.81], "initial_stress": ' &
            //'{"type": "k0", "k0": 12}'), [character(len=200) :: "initial_stress.k0"], &
            "k0 of 12")
        call expect_error(suite, case_text(extra='"gravity": [0, -9.81], "initial_stress": ' &
            //'{"type": "none", "k0": 0.5}'), [character(len=200) :: &
            'initial_stress.k0 only applies to initial_stress.type = "k0"'], "k0 without k0 type")
        call expect_error(suite, case_text(extra='"gravity": [3, -9.81], "initial_stress": ' &
            //'{"type": "k0"}'), [character(len=200) :: 'initial_stress.type = "k0" needs ' &
            //"gravity along -y (the vertical of a 2D case) and no other component; gravity " &
            //"= (3, -9.81) m/s2"], "k0 with tilted gravity")
        call expect_error(suite, case_text(extra='"initial_stress": {"type": "k0"}'), &
            [character(len=200) :: "needs gravity along -y"], "k0 without gravity")
        call expect_error(suite, case_text(extra='"gravity": [0, -9.81], "initial_stress": ' &
            //'{"type": "geostatic"}'), [character(len=200) :: "initial_stress.type", &
            '"none", "k0"'], "unknown initial stress type")
        call expect_error(suite, "{"//domain_2d//", "//materials_1//', "load_state": "' &
            //state_file//'", "gravity": [0, -9.81], "time": {"tend": 1}, "initial_stress": ' &
            //'{"type": "k0"}}', [character(len=200) :: 'initial_stress.type = "k0" cannot be ' &
            //"used with load_state"], "k0 with load_state")
        call expect_error(suite, "{"//domain_2d//', "materials": [{"name": "soil", "type": ' &
            //'"tresca", '//elastic_part//', "Su": 0, "Su_gradient": 1500, "Su_elevation": 0.2}]' &
            //', "load_state": "'//state_file//'", "time": {"tend": 1}}', [character(len=200) :: &
            'materials[1] "soil" takes a state from the initial position of each particle', &
            "the state file of load_state does not keep"], "Su gradient with load_state")
        ! strength_reduction
        call expect_error(suite, case_text(extra='"strength_reduction": {"displacement_limit": ' &
            //'0.1}'), [character(len=200) :: "strength_reduction: no material of the case has " &
            //"a shear strength to reduce"], "strength reduction of an elastic case")
        call expect_error(suite, case_text(materials=mc_soil, extra='"strength_reduction": ' &
            //'{"factor_max": 2}'), [character(len=200) :: &
            "missing required key 'strength_reduction.displacement_limit'"], &
            "strength reduction without a limit")
        call expect_error(suite, case_text(materials=mc_soil, extra='"strength_reduction": ' &
            //'{"factor_min": 1.5, "factor_max": 1.2, "displacement_limit": 0.1}'), &
            [character(len=200) :: "strength_reduction.factor_max = 1.2 is out of range: " &
            //"must be > 1.5"], "strength reduction bracket reversed")
        call expect_error(suite, case_text(materials=mc_soil, extra='"strength_reduction": ' &
            //'{"factor_max": 1.5, "tolerance": 0.6, "displacement_limit": 0.1}'), &
            [character(len=200) :: "strength_reduction.tolerance = 0.6 is out of range: " &
            //"must be > 0 and < 0.5"], "strength reduction tolerance wider than the bracket")
        call expect_error(suite, case_text(materials=mc_soil, extra='"strength_reduction": ' &
            //'{"displacement_limit": 0.1, "rest_ratio": 1}'), [character(len=200) :: &
            "strength_reduction.rest_ratio = 1 is out of range"], "strength reduction rest ratio")
        call expect_error(suite, case_text(materials=mc_soil, extra='"strength_reduction": ' &
            //'{"displacement_limit": 0.1, "factors": [1, 2]}'), [character(len=200) :: &
            "strength_reduction", "factors"], "strength reduction unknown key")
        ! loads
        call expect_error(suite, case_text(extra='"loads": [{"type": "traction", "min": [0, ' &
            //'0.1], "max": [0.5, 0.2], "surface": "+y", "pressure": 1}]'), &
            [character(len=200) :: "loads[1]: the box min = (0, 0.1) m, max = (0.5, 0.2) m " &
            //"is not inside the domain from (0, 0) to (0.4, 0.2) m"], "traction box outside")
        call expect_error(suite, case_text(extra='"loads": [{"type": "point", "position": ' &
            //'[0.1, 0.3], "force": [0, 1]}]'), [character(len=200) :: "loads[1].position = " &
            //"(0.1, 0.3) m is outside the domain"], "point load outside")
        call expect_error(suite, case_text(extra='"loads": [{"type": "traction", "min": [0, ' &
            //'0.1], "max": [0.2, 0.2], "surface": "top", "pressure": 1}]'), &
            [character(len=200) :: "loads[1].surface", '"+y"'], "unknown surface")
        call expect_error(suite, case_text(extra='"loads": [{"type": "traction", "min": [0, ' &
            //'0.1], "max": [0.2, 0.2], "surface": "+y"}]'), [character(len=200) :: &
            "loads[1]: a traction needs 'pressure'"], "traction without a value")
        call expect_error(suite, case_text(extra='"loads": [{"type": "traction", "min": [0, ' &
            //'0.1], "max": [0.2, 0.2], "surface": "+y", "pressure": 1, "force": [0, 1]}]'), &
            [character(len=200) :: 'loads[1].force only applies to a load of type "point"'], &
            "key of another type")
        call expect_error(suite, case_text(extra='"loads": [{"type": "body_force", ' &
            //'"material": "clay", "acceleration": [1, 0]}]'), [character(len=200) :: &
            'loads[1].material = "clay" is not a material of this case'], "unknown material")
        call expect_error(suite, case_text(extra='"loads": [{"type": "body_force", ' &
            //'"material": "soil", "acceleration": [1, 0], "time_function": {"type": "ramp", ' &
            //'"duration": 0}}]'), [character(len=200) :: &
            "loads[1].time_function.duration = 0 is out of range: must be > 0"], "ramp of 0 s")
        call expect_error(suite, case_text(extra='"loads": [{"type": "body_force", ' &
            //'"material": "soil", "acceleration": [1, 0], "time_function": {"type": ' &
            //'"constant", "file": "f.csv"}}]'), [character(len=200) :: &
            'loads[1].time_function.file only applies to a time function of type "table"'], &
            "file of a constant")
        call write_text("test_case_errors_table.csv", "time,factor"//new_line("a")//"0, 0" &
            //new_line("a")//"1, 1"//new_line("a")//"1, 2"//new_line("a"))
        call expect_error(suite, case_text(extra='"loads": [{"type": "body_force", ' &
            //'"material": "soil", "acceleration": [1, 0], "time_function": {"type": "table", ' &
            //'"file": "test_case_errors_table.csv"}}]'), [character(len=200) :: &
            'loads[1].time_function.file = "test_case_errors_table.csv": the times must ' &
            //"increase; line 4 has time 1 s after 1 s"], "table not increasing")
        call write_text("test_case_errors_table.csv", "time,factor"//new_line("a")//"0, x" &
            //new_line("a"))
        call expect_error(suite, case_text(extra='"loads": [{"type": "body_force", ' &
            //'"material": "soil", "acceleration": [1, 0], "time_function": {"type": "table", ' &
            //'"file": "test_case_errors_table.csv"}}]'), [character(len=200) :: &
            "line 2 is not two numbers 'time, factor'"], "table with text")
        call delete_file("test_case_errors_table.csv")
        call expect_error(suite, case_text(extra='"loads": [{"type": "body_force", ' &
            //'"material": "soil", "acceleration": [1, 0], "time_function": {"type": "table", ' &
            //'"file": "no_such_table.csv"}}]'), [character(len=200) :: &
            'loads[1].time_function.file = "no_such_table.csv": no such file'], "table missing")
        ! prescribed_motion
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0, 0.1], ' &
            //'"max": [0.2, 0.3], "velocity": [0, -1]}]'), [character(len=200) :: &
            "prescribed_motion[1]: the box min = (0, 0.1) m, max = (0.2, 0.3) m is not inside " &
            //"the domain"], "region outside")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0, 0.1], ' &
            //'"max": [0.2, 0.2]}]'), [character(len=200) :: &
            "missing required key 'prescribed_motion[1].velocity'"], "region without velocity")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0, 0.1], ' &
            //'"max": [0.2, 0.2], "velocity": [0, 0], "components": ["z"]}]'), &
            [character(len=200) :: 'prescribed_motion[1].components[1] = a string ("z") is ' &
            //'not an axis; allowed: "x", "y"'], "component z in 2D")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0, 0.1], ' &
            //'"max": [0.2, 0.2], "velocity": [0, 0], "components": []}]'), &
            [character(len=200) :: "prescribed_motion[1].components is empty"], &
            "no component")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0, 0.1], ' &
            //'"max": [0.2, 0.2], "velocity": [0, -1]}]'), [character(len=200) :: &
            "prescribed_motion[1] starts at its full velocity at t = 0"], "sudden start")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0.01, 0.01], ' &
            //'"max": [0.09, 0.2], "velocity": [0, 0]}]'), [character(len=200) :: &
            "prescribed_motion[1]: its box min = (0.01, 0.01) m, max = (0.09, 0.2) m holds no " &
            //"node of the grid"], "region without a node")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"min": [0, 0.1], ' &
            //'"max": [0.2, 0.2], "velocity": [0, 0]}, {"min": [0.1, 0.1], "max": [0.3, 0.2], ' &
            //'"velocity": [0, 0]}]'), [character(len=200) :: "prescribed_motion[2]: its box " &
            //"min = (0.1, 0.1) m, max = (0.3, 0.2) m overlaps that of prescribed_motion[1]"], &
            "overlapping regions")
        call expect_error(suite, case_text(extra='"prescribed_motion": [{"name": "a b", ' &
            //'"min": [0, 0.1], "max": [0.2, 0.2], "velocity": [0, 0]}]'), &
            [character(len=200) :: 'prescribed_motion[1].name = "a b" names columns of ' &
            //"history.csv"], "region name with a space")
        ! rigid bodies
        call expect_error(suite, case_text(materials=rigid_materials, bodies=rigid_bodies, &
            extra='"prescribed_motion": [{"rigid": "soil", "velocity": [0, 0]}]'), &
            [character(len=200) :: 'prescribed_motion[1].rigid = "soil" is a material of ' &
            //'type "linear_elastic"; a rigid body is a material of type "rigid"'], &
            "rigid: a deformable material")
        call expect_error(suite, case_text(materials=rigid_materials, bodies=rigid_bodies, &
            extra='"prescribed_motion": [{"rigid": "lead", "velocity": [0, 0]}]'), &
            [character(len=200) :: 'prescribed_motion[1].rigid = "lead" is not a material of ' &
            //"this case"], "rigid: no such material")
        call expect_error(suite, case_text(materials=rigid_materials, bodies=rigid_bodies, &
            extra='"prescribed_motion": [{"rigid": "steel", "min": [0, 0.1], "max": [0.2, ' &
            //'0.2], "velocity": [0, 0]}]'), [character(len=200) :: 'prescribed_motion[1] ' &
            //'pushes the rigid body "steel", whose nodes are those its particles fill: ' &
            //"remove min and max"], "rigid with a box")
        call expect_error(suite, case_text(materials=rigid_materials, bodies=rigid_bodies, &
            extra='"prescribed_motion": [{"rigid": "steel", "velocity": [0, 0]}, {"name": ' &
            //'"again", "rigid": "steel", "velocity": [0, 0]}]'), [character(len=200) :: &
            'prescribed_motion[2].rigid = "steel" is pushed by prescribed_motion[1] already'], &
            "rigid pushed twice")
        call expect_error(suite, case_text(materials=rigid_materials), [character(len=200) :: &
            'materials[2] "steel" is a rigid body that no body of the case fills'], &
            "rigid material without a body")
        call expect_error(suite, case_text(materials=rigid_materials, bodies='"bodies": [{' &
            //'"material": "steel", "min": [0, 0], "max": [0.2, 0.1]}]'), &
            [character(len=200) :: "every body of the case is rigid"], "only rigid bodies")
        call expect_error(suite, case_text(materials=rigid_materials, bodies=rigid_bodies, &
            extra='"prescribed_motion": [{"rigid": "steel", "velocity": [0, -1]}]'), &
            [character(len=200) :: "prescribed_motion[1] starts at its full velocity at t = 0"], &
            "rigid: sudden start")
        call expect_error(suite, case_text(materials='"materials": [{"name": "soil", "type": ' &
            //'"linear_elastic", "E": 1e6, "nu": 0.0, "rho": 1000}, {"name": "st eel", "type": ' &
            //'"rigid", "rho": 7800}]', bodies='"bodies": [{"material": "soil", "min": [0, 0], ' &
            //'"max": [0.2, 0.1]}, {"material": "st eel", "min": [0.3, 0], "max": [0.4, 0.1]}]'), &
            [character(len=200) :: 'materials[2] "st eel" is a free rigid body, whose name ' &
            //"names its columns of history.csv"], "free rigid body with a space in its name")
        call expect_error(suite, case_text(materials='"materials": [{"name": "steel", "type": ' &
            //'"rigid", "rho": 0}]'), [character(len=200) :: "materials[1].rho"], &
            "rigid: density zero")
    end subroutine test_section_errors

    subroutine test_document_errors()
        character(len=*), parameter :: nl = new_line("a")

        ! the comma after line 3 is missing: the parser stops at the start of line 4
        call expect_error(suite, "{"//nl//domain_2d//","//nl//materials_1//nl//bodies_1//","//nl &
            //time_1//"}", [character(len=200) :: "invalid JSON at line 4"], "JSON syntax error")
        call expect_error(suite, "", [character(len=200) :: "empty"], "empty text")
        call expect_error(suite, "   ", [character(len=200) :: "empty"], "blank text")
        call expect_error(suite, "[1, 2]", [character(len=200) :: &
            "the top level must be a JSON object", "found an array"], "top-level array")
        call expect_error(suite, "42", [character(len=200) :: &
            "the top level must be a JSON object", "found a number (42)"], "top-level number")
        call expect_error(suite, case_text(domain='"domain": [4, 2]'), [character(len=200) :: &
            "domain has the wrong type: expected an object, found an array"], "domain array")
        call expect_error(suite, case_text(materials='"materials": [1]'), [character(len=200) :: &
            "materials[1] has the wrong type: expected an object"], "material not an object")
    end subroutine test_document_errors

    !> Strength parameters: ranges (in degrees), psi <= phi, the apex, phi = c = 0, the cone.
    subroutine test_strength_errors()
        character(len=*), parameter :: mc = '"type": "mohr_coulomb", '//elastic_part//", "

        call expect_error(suite, soil_case(mc//'"phi": 30, "c": 10, "separation": true'), &
            [character(len=200) :: "materials[1].separation = true needs a stress-free apex: " &
            //"c = 10 Pa here; give c = 0 or tension_cutoff = 0"], "separation with cohesion")
        call expect_error(suite, soil_case(mc//'"phi": 30, "separation": 1'), &
            [character(len=200) :: "materials[1].separation"], "separation not a boolean")
        call expect_error(suite, case_text(extra='"solver": {"locking_correction": "bbar"}'), &
            [character(len=200) :: 'solver.locking_correction = "bbar" is not allowed: must ' &
            //'be one of "none", "fbar"'], "unknown locking correction")
        call expect_error(suite, case_text(extra='"solver": {"transfer": "apic", "flip_fraction": 0.9}'), &
            [character(len=200) :: 'solver.flip_fraction applies to solver.transfer = "flip" ' &
            //'only'], "flip_fraction with APIC")
        call expect_error(suite, case_text(extra='"solver": {"flip_fraction": 1.5}'), &
            [character(len=200) :: "solver.flip_fraction = 1.5"], "flip_fraction above 1")
        call expect_error(suite, case_text(extra='"solver": {"transfer": "xpic", "flip_fraction": 0.9}'), &
            [character(len=200) :: 'solver.flip_fraction applies to solver.transfer = "flip" ' &
            //'only (here "xpic"'], "flip_fraction with XPIC")
        call expect_error(suite, case_text(extra='"solver": {"xpic_order": 3}'), &
            [character(len=200) :: 'solver.xpic_order applies to solver.transfer = "xpic" only'], &
            "xpic_order with FLIP")
        call expect_error(suite, case_text(extra='"solver": {"transfer": "xpic", "xpic_order": 0}'), &
            [character(len=200) :: "solver.xpic_order = 0 is out of range"], "xpic_order 0")
        call expect_error(suite, case_text(extra='"solver": {"transfer": "xpic", "xpic_order": 2.5}'), &
            [character(len=200) :: "solver.xpic_order"], "xpic_order not an integer")
        call expect_error(suite, soil_case(mc//'"phi": 90'), [character(len=200) :: &
            "materials[1].phi = 90 is out of range: must be >= 0 and < 90 [deg]"], "phi = 90")
        call expect_error(suite, soil_case(mc//'"phi": -1'), [character(len=200) :: &
            "materials[1].phi = -1 is out of range: must be >= 0 and < 90 [deg]"], "phi < 0")
        call expect_error(suite, soil_case(mc//'"c": 1000'), [character(len=200) :: &
            "missing required key 'materials[1].phi' (a number >= 0 and < 90 [deg])"], &
            "phi missing")
        call expect_error(suite, soil_case(mc//'"phi": 30, "psi": 35'), [character(len=200) :: &
            "materials[1].psi = 35 deg is above materials[1].phi = 30 deg", &
            "must be >= 0 and <= phi = 30 [deg]"], "psi > phi")
        call expect_error(suite, soil_case(mc//'"phi": 30, "psi": -2'), [character(len=200) :: &
            "materials[1].psi = -2 is out of range: must be >= 0 [deg]"], "psi < 0")
        call expect_error(suite, soil_case(mc//'"phi": 30, "c": -5'), [character(len=200) :: &
            "materials[1].c = -5 is out of range: must be >= 0 [Pa]"], "c < 0")
        ! apex c / tan(phi) = 1000 / tan(30 deg) = 1732.0508 Pa
        call expect_error(suite, soil_case(mc//'"phi": 30, "c": 1000, "tension_cutoff": 2000'), &
            [character(len=200) :: "materials[1].tension_cutoff = 2000 Pa is above the apex " &
            //"of the yield surface, c / tan(phi) = 1732.05 Pa", "c = 1000 Pa, phi = 30 deg", &
            "must be >= 0 and <= 1732.05 [Pa]"], "tension cutoff above the apex")
        call expect_error(suite, soil_case(mc//'"phi": 30, "tension_cutoff": 1'), &
            [character(len=200) :: "materials[1].tension_cutoff = 1 Pa is above the apex", &
            "c / tan(phi) = 0 Pa"], "tension cutoff of a cohesionless soil")
        call expect_error(suite, soil_case(mc//'"phi": 30, "c": 1000, "tension_cutoff": -1'), &
            [character(len=200) :: &
            "materials[1].tension_cutoff = -1 is out of range: must be >= 0 [Pa]"], &
            "negative tension cutoff")
        call expect_error(suite, soil_case(mc//'"phi": 0, "c": 0'), [character(len=200) :: &
            "materials[1].phi = 0 and materials[1].c = 0", "a Mohr-Coulomb material with " &
            //"phi = 0 and c = 0 has no strength; use a newtonian fluid"], "phi = c = 0")
        call expect_error(suite, soil_case(mc//'"phi": 0'), [character(len=200) :: &
            "a Mohr-Coulomb material with phi = 0 and c = 0 has no strength"], &
            "phi = 0 with c defaulting to 0")
        call expect_error(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 0'), &
            [character(len=200) :: "a Drucker-Prager material with phi = 0 and c = 0 has no " &
            //"strength"], "Drucker-Prager phi = c = 0")
        call expect_error(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 30, ' &
            //'"cone": "outer"'), [character(len=200) :: 'materials[1].cone = "outer" is not ' &
            //'allowed: must be one of "plane_strain", "compression", "extension"'], &
            "unknown cone")
        call expect_error(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 30, ' &
            //'"cone": 1'), [character(len=200) :: "materials[1].cone has the wrong type"], &
            "cone not a string")
    end subroutine test_strength_errors

    !> Softening: type, residual values not above peak, a positive strain.
    subroutine test_softening_errors()
        character(len=*), parameter :: mc = '"type": "mohr_coulomb", '//elastic_part &
            //', "phi": 30, "c": 1000, "psi": 10, '

        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "phi_residual": 35, ' &
            //'"strain": 0.1}'), [character(len=200) :: "materials[1].softening.phi_residual " &
            //"= 35 deg is above the peak value materials[1].phi = 30 deg: residual strength " &
            //"above peak", "must be >= 0 and <= 30 [deg]"], "residual phi above peak")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "c_residual": 2000, ' &
            //'"strain": 0.1}'), [character(len=200) :: "materials[1].softening.c_residual " &
            //"= 2000 Pa is above the peak value materials[1].c = 1000 Pa: residual strength " &
            //"above peak"], "residual c above peak")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "psi_residual": 12, ' &
            //'"strain": 0.1}'), [character(len=200) :: "materials[1].softening.psi_residual " &
            //"= 12 deg is above the peak value materials[1].psi = 10 deg"], &
            "residual psi above peak")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "phi_residual": 5, ' &
            //'"psi_residual": 8, "strain": 0.1}'), [character(len=200) :: &
            "materials[1].softening.psi_residual = 8 deg is above the residual friction " &
            //"angle 5 deg"], &
            "residual psi above residual phi")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "phi_residual": 0, ' &
            //'"c_residual": 0, "strain": 0.1}'), [character(len=200) :: &
            "materials[1].softening: phi_residual = 0 and c_residual = 0 leave no strength"], &
            "no residual strength")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "phi_residual": -1, ' &
            //'"strain": 0.1}'), [character(len=200) :: "materials[1].softening.phi_residual" &
            //" = -1 is out of range: must be >= 0 [deg]"], "negative residual phi")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "exponential", "strain": 0}'), &
            [character(len=200) :: &
            "materials[1].softening.strain = 0 is out of range: must be > 0"], "strain = 0")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "strain": -0.1}'), &
            [character(len=200) :: &
            "materials[1].softening.strain = -0.1 is out of range: must be > 0"], "strain < 0")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "c_residual": 0}'), &
            [character(len=200) :: "missing required key 'materials[1].softening.strain' " &
            //"(a number > 0)"], "softening without strain")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "none", "strain": 0.1}'), &
            [character(len=200) :: "materials[1].softening.strain only applies to " &
            //'softening.type = "linear" or "exponential" (here "none")'], &
            "strain with softening none")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "cubic"}'), &
            [character(len=200) :: 'materials[1].softening.type = "cubic" is not allowed: ' &
            //'must be one of "none", "linear", "exponential"'], "unknown softening type")
        call expect_error(suite, soil_case(mc//'"softening": {"strain": 0.1}'), &
            [character(len=200) :: "missing required key 'materials[1].softening.type'"], &
            "softening without type")
        call expect_error(suite, soil_case(mc//'"softening": {"type": "linear", "strian": 0.1}'), &
            [character(len=200) :: "unknown key 'materials[1].softening.strian'; did you " &
            //"mean 'strain'?"], "misspelt softening key")
        call expect_error(suite, soil_case(mc//'"softening": "linear"'), [character(len=200) :: &
            "materials[1].softening has the wrong type: expected an object"], &
            "softening not an object")
    end subroutine test_softening_errors

    !> The keys allowed in a material depend on its type.
    subroutine test_material_key_errors()
        call expect_error(suite, soil_case('"type": "newtonian", "E": 1e6, "rho": 1000, ' &
            //'"viscosity": 1e-3, "bulk_modulus": 2.2e9'), [character(len=200) :: &
            "unknown key 'materials[1].E'", "E is not a parameter of a newtonian material", &
            "the keys of a newtonian material are: name, type, rho, viscosity, bulk_modulus"], &
            "E in a newtonian material")
        call expect_error(suite, soil_case('"type": "linear_elastic", '//elastic_part//', "phi": 30'), &
            [character(len=200) :: "unknown key 'materials[1].phi'", "phi is not a parameter " &
            //"of a linear_elastic material; the keys of a linear_elastic material are: " &
            //"name, type, E, nu, rho"], "phi in an elastic material")
        call expect_error(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phi": 30, ' &
            //'"cone": "compression"'), [character(len=200) :: "unknown key " &
            //"'materials[1].cone'", "cone is not a parameter of a mohr_coulomb material", &
            "name, type, E, nu, rho, phi, c, psi, tension_cutoff, softening"], &
            "cone in a Mohr-Coulomb material")
        call expect_error(suite, soil_case('"type": "mohr_coulomb", '//elastic_part//', "phy": 30'), &
            [character(len=200) :: "unknown key 'materials[1].phy'; did you mean 'phi'? The " &
            //"keys of a mohr_coulomb material are: name, type, E"], "misspelt phi")
        call expect_error(suite, soil_case('"type": "drucker_prager", '//elastic_part//', "phi": 30, ' &
            //'"Cone": "compression"'), [character(len=200) :: "unknown key " &
            //"'materials[1].Cone'; did you mean 'cone'? (keys are case-sensitive)"], &
            "cone in the wrong case")
        call expect_error(suite, soil_case('"tpye": "elastic", '//elastic_part), &
            [character(len=200) :: "unknown key 'materials[1].tpye'; did you mean 'type'?"], &
            "misspelt type")
        call expect_error(suite, soil_case(elastic_part), [character(len=200) :: "missing required " &
            //"key 'materials[1].type' (one of ""linear_elastic"", ""elastic"", " &
            //"""mohr_coulomb"", ""drucker_prager"", ""newtonian"", ""neo_hookean"", ""mu_i"", ""tresca"", " &
            //"""rigid"", ""cam_clay"", ""mcc"")"], &
            "type missing")
        call expect_error(suite, soil_case('"type": "mohr-coulomb", '//elastic_part//', "phi": 30'), &
            [character(len=200) :: 'materials[1].type = "mohr-coulomb" is not allowed'], &
            "mohr-coulomb with a hyphen")
    end subroutine test_material_key_errors

    subroutine test_newtonian_errors()
        character(len=*), parameter :: fluid = '"type": "newtonian", "rho": 1000, '

        call expect_error(suite, soil_case(fluid//'"viscosity": -1, "bulk_modulus": 2.2e9'), &
            [character(len=200) :: &
            "materials[1].viscosity = -1 is out of range: must be >= 0 [Pa s]"], &
            "viscosity < 0")
        call expect_error(suite, soil_case(fluid//'"viscosity": 1e-3, "bulk_modulus": 0'), &
            [character(len=200) :: &
            "materials[1].bulk_modulus = 0 is out of range: must be > 0 [Pa]"], &
            "bulk_modulus = 0")
        call expect_error(suite, soil_case(fluid//'"bulk_modulus": 2.2e9'), [character(len=200) :: &
            "missing required key 'materials[1].viscosity' (a number >= 0 [Pa s])"], &
            "viscosity missing")
        call expect_error(suite, soil_case(fluid//'"viscosity": 1e-3'), [character(len=200) :: &
            "missing required key 'materials[1].bulk_modulus' (a number > 0 [Pa])"], &
            "bulk_modulus missing")
    end subroutine test_newtonian_errors

end program test_mpm_case_errors
