!> The `bodies` key of a case: boxes, 2D polygons, circles (2D), spheres and cylinders (3D)
!> or closed STL surfaces filled with particles.
module mpm_case_bodies
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_strings, only: int_text, fmt_real, fmt_vector, fmt_box, same
    use mpm_stl, only: read_stl
    use mpm_surface_mesh, only: stl_mesh_type, check_closed
    use mpm_polygon, only: polygon_area, polygon_crossing, polygon_walls
    use mpm_case_cursor, only: cursor_type
    use mpm_case_domain, only: domain_section_type
    use mpm_case_particles, only: particles_section_type
    use mpm_case_materials, only: material_spec_type, material_index, material_list
    use mpm_case_particle_list, only: particle_list_type, read_particle_list
    implicit none
    private
    public :: body_spec_type, read_bodies, body_keys, body_count_interface, &
        body_overlap_interface, domain_digits, round_keys, cylinder_keys, inside_shape, &
        is_box, shape_none, shape_circle, shape_sphere, shape_cylinder

    character(len=*), parameter :: body_keys(*) = [character(len=13) :: "name", "material", &
        "min", "max", "velocity", "file", "scale", "offset", "polygon", "circle", "sphere", &
        "cylinder", "top", "bottom", "particle_list"]
        !! keys of an item of `bodies`
    character(len=*), parameter :: round_keys(*) = [character(len=6) :: "center", "radius"]
        !! keys of `bodies[i].circle` and `bodies[i].sphere`
    character(len=*), parameter :: cylinder_keys(*) = [character(len=6) :: "start", "end", &
        "radius"]
        !! keys of `bodies[i].cylinder`
    ! analytic shapes of a body
    integer, parameter :: shape_none = 0      !! a box, a polygon or a surface
    integer, parameter :: shape_circle = 1    !! a disc (2D)
    integer, parameter :: shape_sphere = 2    !! a ball (3D)
    integer, parameter :: shape_cylinder = 3  !! a finite solid cylinder (3D)
    character(len=*), parameter :: shape_names(3) = [character(len=8) :: "circle", "sphere", &
        "cylinder"]
        !! the keys of the shapes
    character(len=*), parameter :: body_stl_keys(*) = [character(len=6) :: "scale", "offset"]
        !! keys of a body that only apply with `file`
    real(wp), parameter :: box_tolerance = 1.0e-9_wp
        !! tolerance of box tests, relative to dx: absorbs round-off of corners like 3*0.1
    integer, parameter :: domain_digits = 12
        !! significant digits of computed coordinates (origin + n dx) in messages

    !> A body of particles of one material: a box, a 2D polygon, or the inside of a closed
    !> STL surface.
    type :: body_spec_type
        character(len=:), allocatable :: name
            !! name of the body (for messages and output)
        integer :: material = 0
            !! index into case%materials
        real(wp) :: xmin(3) = 0.0_wp
            !! lower corner of the box (of the bounding box of a polygon or a surface) [m]
        real(wp) :: xmax(3) = 0.0_wp
            !! upper corner of the box (of the bounding box of a polygon or a surface) [m]
        real(wp) :: velocity(3) = 0.0_wp
            !! initial velocity [m/s]
        character(len=:), allocatable :: file
            !! STL file of the closed surface ("" for a box or a polygon)
        real(wp), allocatable :: polygon(:, :)
            !! (2, vertices) a 2D polygon body's vertices in order; not allocated otherwise [m]
        real(wp) :: scale = 1.0_wp
            !! factor applied to the STL coordinates before `offset` [m per unit]
        real(wp) :: offset(3) = 0.0_wp
            !! translation added to the scaled STL coordinates [m]
        real(wp), allocatable :: triangle(:, :, :)
            !! corners (coordinate, corner 1..3, triangle) of the closed surface after scale and
            !! offset, or of the walls of a polygon extruded across z = 0 (mpm_polygon::
            !! polygon_walls); not allocated for a box [m]
        integer :: shape = shape_none
            !! an analytic shape: shape_circle, shape_sphere, shape_cylinder
        real(wp) :: centre(3) = 0.0_wp
            !! centre of a circle or a sphere, centre of the start face of a cylinder [m]
        real(wp) :: axis_end(3) = 0.0_wp
            !! centre of the end face of a cylinder [m]
        real(wp) :: radius = 0.0_wp
            !! radius of the shape [m]
        character(len=:), allocatable :: bottom_file
            !! a layer's lower surface (STL file; `file` holds its upper one); not allocated for
            !! other bodies
        real(wp), allocatable :: bottom(:, :, :)
            !! a layer's lower surface (coordinate, corner, triangle), after scale and offset;
            !! `triangle` holds its upper one [m]
        type(particle_list_type), allocatable :: list
            !! the particles of a `particle_list` body (its sites are none)
        integer(i8) :: particles = -1
            !! particles the body holds, counted by the reader (-1: not counted)
    end type body_spec_type

    abstract interface
        !> Number of particles body b holds; -1 when the memory to fill an STL body is missing.
        integer(i8) function body_count_interface(dim, domain, particles, bodies, b)
            import :: i8, domain_section_type, particles_section_type, body_spec_type
            integer, intent(in) :: dim
                !! number of space dimensions
            type(domain_section_type), intent(in) :: domain
                !! the grid
            type(particles_section_type), intent(in) :: particles
                !! particles per cell and their placement
            type(body_spec_type), intent(in) :: bodies(:)
                !! bodies 1..b set
            integer, intent(in) :: b
                !! body index
        end function body_count_interface

        !> Number of particle sites bodies i and j both hold (j < i); -1 when the memory to
        !> test them is missing.
        integer(i8) function body_overlap_interface(dim, domain, particles, bodies, i, j)
            import :: i8, domain_section_type, particles_section_type, body_spec_type
            integer, intent(in) :: dim
                !! number of space dimensions
            type(domain_section_type), intent(in) :: domain
                !! the grid
            type(particles_section_type), intent(in) :: particles
                !! particles per cell and their placement
            type(body_spec_type), intent(in) :: bodies(:)
                !! bodies 1..i set
            integer, intent(in) :: i, j
                !! the two bodies
        end function body_overlap_interface
    end interface

contains

    !> `bodies`: boxes, 2D polygons or closed STL surfaces filled with particles, inside the
    !> domain, each with particles, no two holding the same particle site.
    subroutine read_bodies(root, dim, domain, particles, materials, load_state, count, &
            overlap, bodies, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        character(len=*), intent(in) :: load_state
            !! state file the particles come from ("" for none)
        procedure(body_count_interface) :: count
            !! particles a body holds (the case layer's geometry, mpm_case_sites)
        procedure(body_overlap_interface) :: overlap
            !! particle sites two bodies both hold (mpm_case_sites)
        type(body_spec_type), allocatable, intent(out) :: bodies(:)
            !! the bodies, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: list, item
        character(len=:), allocatable :: path, material
        integer :: i, j
        integer(i8) :: total

        if (len(load_state) > 0) then
            if (root%has("bodies")) then
                call root%fail(error, "bodies cannot be given together with load_state: " &
                    //"the particles come from the state file '"//load_state//"'; " &
                    //"remove the bodies or remove load_state")
                return
            end if
            allocate (bodies(0))
            return
        end if
        if (.not. root%has("bodies")) then
            call root%fail(error, "missing required key 'bodies' (an array of boxes, 2D " &
                //"polygons or closed STL surfaces of particles); give load_state instead to " &
                //"start from a saved state")
            return
        end if
        call root%get_list("bodies", "body", list, error)
        if (allocated(error)) return
        allocate (bodies(list%size()))
        total = 0
        do i = 1, size(bodies)
            item = list%item(i)
            path = item%path
            call item%check_object(body_keys, error)
            if (allocated(error)) return
            associate (body => bodies(i))
                body%name = "body"//int_text(i)
                call item%get_string("name", body%name, error)
                if (allocated(error)) return
                do j = 1, i - 1
                    if (same(bodies(j)%name, body%name)) then
                        call root%fail(error, path//'.name = "'//body%name//'" is ' &
                            //"already the name of bodies["//int_text(j)//"]; body names must " &
                            //"be unique")
                        return
                    end if
                end do
                material = ""
                call item%get_string("material", material, error, required=.true.)
                if (allocated(error)) return
                body%material = material_index(materials, material)
                if (body%material == 0) then
                    call root%fail(error, path//'.material = "'//material//'" is not a ' &
                        //"material of this case; the materials are: " &
                        //material_list(materials))
                    return
                end if
                if (item%has("particle_list")) then
                    call read_body_list(item, dim, domain, materials, body, error)
                    if (allocated(error)) return
                else if (item%has("top") .or. item%has("bottom")) then
                    call read_body_layer(item, dim, body, error)
                    if (allocated(error)) return
                else if (item%has("file")) then
                    call read_body_surface(item, dim, body, error)
                    if (allocated(error)) return
                else if (item%has("polygon")) then
                    call read_body_polygon(item, dim, domain%dx, body, error)
                    if (allocated(error)) return
                else if (item%has("circle") .or. item%has("sphere") .or. item%has("cylinder")) then
                    call read_body_shape(item, dim, body, error)
                    if (allocated(error)) return
                else
                    if (.not. (item%has("min") &
                        .or. item%has("max"))) then
                        call root%fail(error, path//' "'//body%name//'": give one of ' &
                            //"'min' and 'max' (a box), 'polygon' or 'circle' (2D), 'sphere' " &
                            //"or 'cylinder' (3D), 'file' (a closed STL surface), 'top' and " &
                            //"'bottom' (a layer) or 'particle_list'; none was given")
                        return
                    end if
                    do j = 1, 2
                        if (item%has(trim(body_stl_keys(j)))) then
                            call root%fail(error, path//"."//trim(body_stl_keys(j)) &
                                //" only applies to a body given by 'file' (a closed STL " &
                                //"surface) or by 'top' and 'bottom' (a layer); remove it")
                            return
                        end if
                    end do
                    call item%get_vector("min", dim, body%xmin, error, &
                        required=.true., unit="m")
                    if (allocated(error)) return
                    call item%get_vector("max", dim, body%xmax, error, &
                        required=.true., unit="m")
                    if (allocated(error)) return
                end if
                call item%get_vector("velocity", dim, body%velocity, error, &
                    unit="m/s")
                if (allocated(error)) return
            end associate
            call check_body_box(root, dim, domain, particles, count, overlap, bodies, i, &
                error)
            if (allocated(error)) return
            total = total + bodies(i)%particles
        end do
        if (total > huge(1)) then
            call root%fail(error, "the bodies hold "//int_text(total)//" particles, more " &
                //"than the "//int_text(huge(1))//" this version can store; use a smaller " &
                //"particles.ppc or a larger domain.dx")
        end if
    end subroutine read_bodies

    !> An STL body (`file`, `scale`, `offset`): reads the surface, refuses an open one or one
    !> given together with `min`/`max`, and sets min/max to its bounding box.
    subroutine read_body_surface(item, dim, body, error)
        type(cursor_type), intent(in) :: item
            !! the body's object ("bodies[i]")
        integer, intent(in) :: dim
            !! number of space dimensions
        type(body_spec_type), intent(inout) :: body
            !! the body (name set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(stl_mesh_type) :: mesh
        type(error_type), allocatable :: stl_error
        character(len=:), allocatable :: path, label, message
        logical :: closed

        path = item%path
        label = path//' "'//body%name//'"'
        if (item%has("min") .or. item%has("max") .or. item%has("polygon") .or. &
            has_shape(item)) then
            call item%fail(error, label//": give one of 'file' (a closed STL surface), " &
                //"'min' and 'max' (a box), 'polygon', 'circle', 'sphere' or 'cylinder', " &
                //"not several")
            return
        end if
        call item%get_real("scale", body%scale, error, above=0.0_wp)
        if (allocated(error)) return
        call item%get_vector("offset", 3, body%offset, error, unit="m")
        if (allocated(error)) return
        call read_surface_file(item, "file", body%scale, body%offset, body%file, mesh, error)
        if (allocated(error)) return
        call check_closed(mesh, closed, message, stl_error)
        if (allocated(stl_error)) then
            call fatal_error(error, item%src//": "//stl_error%message, stl_error%code)
            return
        end if
        if (.not. closed) then
            call item%fail(error, label//": the surface '"//body%file//"' is not closed: " &
                //message//"; a body needs a closed surface")
            return
        end if
        body%xmin = mesh%lo
        body%xmax = mesh%hi
        call move_alloc(mesh%vertex, body%triangle)
        if (dim == 2 .and. .not. (body%xmin(3) < 0.0_wp .and. 0.0_wp < body%xmax(3))) then
            call item%fail(error, label//": the surface '"//body%file//"' spans z = " &
                //fmt_real(body%xmin(3))//" .. "//fmt_real(body%xmax(3))//" [m]; a 2D body " &
                //"is its section by the plane z = 0, which must cross the surface")
        end if
    end subroutine read_body_surface

    !> A body of listed particles (`particle_list`, a CSV file; mpm_case_particle_list): no
    !> other geometry key; its min/max become the bounding box of the positions.
    subroutine read_body_list(item, dim, domain, materials, body, error)
        type(cursor_type), intent(in) :: item
            !! the body's object ("bodies[i]")
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(material_spec_type), intent(in) :: materials(:)
            !! the case's materials
        type(body_spec_type), intent(inout) :: body
            !! the body (name and material set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: others(*) = [character(len=8) :: "min", "max", &
            "polygon", "file", "circle", "sphere", "cylinder", "top", "bottom", "scale", "offset"]
        integer :: k

        do k = 1, size(others)
            if (item%has(trim(others(k)))) then
                call item%fail(error, item%path//' "'//body%name//'": a particle_list body ' &
                    //"takes its particles from the file; remove '"//trim(others(k))//"'")
                return
            end if
        end do
        allocate (body%list)
        call read_particle_list(item, dim, domain, materials, body%material, body%list, error)
        if (allocated(error)) return
        body%xmin = minval(body%list%x, dim=2)
        body%xmax = maxval(body%list%x, dim=2)
        body%particles = size(body%list%volume, kind=i8)
    end subroutine read_body_list

    !> A layer between two surfaces (`top`, `bottom`: STL files of height fields, e.g. a
    !> terrain and a slip surface, with the body's `scale` and `offset`): the particles below
    !> the top surface and above the bottom one, where both lie above and below them. Its
    !> bounding box spans the two surfaces' common horizontal extent and their heights.
    subroutine read_body_layer(item, dim, body, error)
        type(cursor_type), intent(in) :: item
            !! the body's object ("bodies[i]")
        integer, intent(in) :: dim
            !! number of space dimensions
        type(body_spec_type), intent(inout) :: body
            !! the body (name set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(stl_mesh_type) :: top, bottom
        character(len=:), allocatable :: label
        character(len=*), parameter :: others(*) = [character(len=8) :: "min", "max", &
            "polygon", "file", "circle", "sphere", "cylinder"]
        integer :: k, w

        label = item%path//' "'//body%name//'"'
        do k = 1, size(others)
            if (item%has(trim(others(k)))) then
                call item%fail(error, label//": give one of 'top' and 'bottom' (a layer), " &
                    //"'min' and 'max' (a box), 'polygon', 'file' or a shape, not several ('" &
                    //trim(others(k))//"' is given too)")
                return
            end if
        end do
        call item%get_real("scale", body%scale, error, above=0.0_wp)
        if (allocated(error)) return
        call item%get_vector("offset", 3, body%offset, error, unit="m")
        if (allocated(error)) return
        call read_surface_file(item, "top", body%scale, body%offset, body%file, top, error)
        if (allocated(error)) return
        call read_surface_file(item, "bottom", body%scale, body%offset, body%bottom_file, &
            bottom, error)
        if (allocated(error)) return
        w = dim
        body%xmin = max(top%lo, bottom%lo)
        body%xmax = min(top%hi, bottom%hi)
        body%xmin(w) = bottom%lo(w)
        body%xmax(w) = top%hi(w)
        if (dim == 2) then
            if (.not. (max(top%lo(3), bottom%lo(3)) < 0.0_wp .and. &
                0.0_wp < min(top%hi(3), bottom%hi(3)))) then
                call item%fail(error, label//": the surfaces 'top' and 'bottom' must both cross " &
                    //"the plane z = 0 (a 2D layer is their section by it)")
                return
            end if
            body%xmin(3) = 0.0_wp
            body%xmax(3) = 0.0_wp
        end if
        if (any(body%xmin(1:dim - 1) >= body%xmax(1:dim - 1))) then
            call item%fail(error, label//": the surfaces 'top' ("//body%file//") and 'bottom' (" &
                //body%bottom_file//") have no horizontal extent in common (bounding boxes " &
                //fmt_box(top%lo(1:dim), top%hi(1:dim))//" and "//fmt_box(bottom%lo(1:dim), &
                bottom%hi(1:dim))//" [m])")
            return
        end if
        call move_alloc(top%vertex, body%triangle)
        call move_alloc(bottom%vertex, body%bottom)
    end subroutine read_body_layer

    !> The STL file of `key` (`file`, or a layer's `top` or `bottom`), found and read with the
    !> body's scale and offset.
    subroutine read_surface_file(item, key, scale, offset, file, mesh, error)
        type(cursor_type), intent(in) :: item
            !! the body's object
        character(len=*), intent(in) :: key
            !! "top" or "bottom"
        real(wp), intent(in) :: scale, offset(3)
            !! the body's scale [m per unit] and offset [m]
        character(len=:), allocatable, intent(out) :: file
            !! the file named
        type(stl_mesh_type), intent(out) :: mesh
            !! its triangles
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(error_type), allocatable :: stl_error
        logical :: exists

        file = ""
        call item%get_path(key, 0, file, error, required=.true.)
        if (allocated(error)) return
        inquire (file=file, exist=exists)
        if (len(file) == 0 .or. .not. exists) then
            call item%fail(error, item%key_path(key)//": STL file '"//file//"' not found " &
                //"(a relative path is taken from the current working directory)")
            return
        end if
        call read_stl(file, mesh, stl_error, scale, offset, item%key_path(key))
        if (allocated(stl_error)) call fatal_error(error, item%src//": "//stl_error%message, &
            stl_error%code)
    end subroutine read_surface_file

    !> A 2D polygon body (`polygon`): its vertices, refused when it is not simple (edges that
    !> cross or touch, a repeated vertex) or has no area, or with `min`, `max`, `scale` or
    !> `offset`; sets min/max to its bounding box and the triangles the filler counts
    !> crossings with (its walls across z = 0).
    subroutine read_body_polygon(item, dim, dx, body, error)
        type(cursor_type), intent(in) :: item
            !! the body's object ("bodies[i]")
        integer, intent(in) :: dim
            !! number of space dimensions
        real(wp), intent(in) :: dx
            !! cell size (the height of the extruded walls) [m]
        type(body_spec_type), intent(inout) :: body
            !! the body (name set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: path, label
        integer :: j, e1, e2

        path = item%path
        label = path//' "'//body%name//'"'
        if (dim /= 2) then
            call item%fail(error, path//".polygon: a polygon body is two-dimensional " &
                //"(dimension = 2); in 3D give a closed STL surface ('file')")
            return
        end if
        if (item%has("min") .or. item%has("max") .or. has_shape(item)) then
            call item%fail(error, label//": give one of 'polygon', 'min' and 'max' (a box) " &
                //"or 'circle', not several")
            return
        end if
        do j = 1, size(body_stl_keys)
            if (item%has(trim(body_stl_keys(j)))) then
                call item%fail(error, path//"."//trim(body_stl_keys(j))//" only applies to " &
                    //"a body given by 'file' (a closed STL surface); remove it")
                return
            end if
        end do
        call item%get_points("polygon", 2, body%polygon, error, required=.true., unit="m", &
            at_least=3)
        if (allocated(error)) return
        call polygon_crossing(body%polygon, e1, e2)
        if (e1 > 0 .and. e1 == e2) then
            call item%fail(error, path//".polygon: vertex "//int_text(e1)//" " &
                //fmt_vector(body%polygon(:, e1))//" is repeated by the vertex after it; " &
                //"give each vertex once")
            return
        else if (e1 > 0) then
            call item%fail(error, path//".polygon crosses itself: the edge from vertex " &
                //int_text(e1)//" "//fmt_vector(body%polygon(:, e1))//" meets the edge from " &
                //"vertex "//int_text(e2)//" "//fmt_vector(body%polygon(:, e2))//"; give the " &
                //"vertices in order around the outline (either sense), the last joined to " &
                //"the first")
            return
        end if
        if (.not. abs(polygon_area(body%polygon)) > 0.0_wp) then
            call item%fail(error, path//".polygon encloses no area; give at least three " &
                //"vertices not on one line")
            return
        end if
        body%xmin(1:2) = minval(body%polygon, dim=2)
        body%xmax(1:2) = maxval(body%polygon, dim=2)
        body%triangle = polygon_walls(body%polygon, dx)
    end subroutine read_body_polygon

    !> A body given by an analytic shape: `circle` (2D) {center, radius}, `sphere` (3D)
    !> {center, radius} or `cylinder` (3D) {start, end, radius}, the centres of its two end
    !> faces; one shape, and none of `min`, `max`, `polygon`, `file`, `scale`, `offset`. Sets
    !> min/max to its bounding box.
    subroutine read_body_shape(item, dim, body, error)
        type(cursor_type), intent(in) :: item
            !! the body's object ("bodies[i]")
        integer, intent(in) :: dim
            !! number of space dimensions
        type(body_spec_type), intent(inout) :: body
            !! the body (name set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: sec
        character(len=:), allocatable :: label, key
        integer :: k, given
        real(wp) :: axis(3), length, reach(3)
        character(len=*), parameter :: others(*) = [character(len=7) :: "min", "max", &
            "polygon", "scale", "offset"]

        label = item%path//' "'//body%name//'"'
        given = 0
        do k = 1, size(shape_names)
            if (item%has(trim(shape_names(k)))) then
                given = given + 1
                body%shape = k
            end if
        end do
        key = trim(shape_names(body%shape))
        if (given > 1) then
            call item%fail(error, label//": give one of 'circle', 'sphere' and 'cylinder', " &
                //"not several")
            return
        end if
        do k = 1, size(others)
            if (item%has(trim(others(k)))) then
                call item%fail(error, label//": give one of '"//key//"', 'min' and 'max' (a " &
                    //"box), 'polygon' or 'file', not several ('"//trim(others(k))//"' is " &
                    //"given too)")
                return
            end if
        end do
        if (body%shape == shape_circle .and. dim /= 2) then
            call item%fail(error, item%key_path("circle")//": a circle is a 2D body; in a 3D " &
                //"case give a 'sphere' or a 'cylinder'")
            return
        else if (body%shape /= shape_circle .and. dim /= 3) then
            call item%fail(error, item%key_path(key)//": a "//key//" is a 3D body; in a 2D " &
                //"case give a 'circle' (or a 'polygon')")
            return
        end if
        if (body%shape == shape_cylinder) then
            call item%get_section(key, cylinder_keys, sec, error, required=.true.)
            if (allocated(error)) return
            call sec%get_vector("start", dim, body%centre, error, required=.true., unit="m")
            if (allocated(error)) return
            call sec%get_vector("end", dim, body%axis_end, error, required=.true., unit="m")
            if (allocated(error)) return
            axis = body%axis_end - body%centre
            length = norm2(axis)
            if (.not. length > 0.0_wp) then
                call sec%fail(error, sec%path//": start and end are the same point " &
                    //fmt_vector(body%centre(1:dim))//" [m]; they are the centres of the " &
                    //"cylinder's two end faces")
                return
            end if
        else
            call item%get_section(key, round_keys, sec, error, required=.true.)
            if (allocated(error)) return
            call sec%get_vector("center", dim, body%centre, error, required=.true., unit="m")
            if (allocated(error)) return
        end if
        call sec%get_real("radius", body%radius, error, required=.true., above=0.0_wp, unit="m")
        if (allocated(error)) return
        if (body%shape == shape_cylinder) then
            ! the end discs reach radius * sqrt(1 - (axis_a / length)^2) along axis a
            reach = body%radius*sqrt(max(0.0_wp, 1.0_wp - (axis/length)**2))
            body%xmin = min(body%centre, body%axis_end) - reach
            body%xmax = max(body%centre, body%axis_end) + reach
        else
            body%xmin = body%centre - body%radius
            body%xmax = body%centre + body%radius
        end if
        body%xmin(dim + 1:) = 0.0_wp
        body%xmax(dim + 1:) = 0.0_wp
    end subroutine read_body_shape

    !> Whether a body's object gives an analytic shape.
    logical function has_shape(item)
        type(cursor_type), intent(in) :: item
            !! the body's object

        has_shape = item%has("circle") .or. item%has("sphere") .or. item%has("cylinder")
    end function has_shape

    !> Whether a point lies inside a body's analytic shape (its boundary included).
    pure logical function inside_shape(body, x)
        type(body_spec_type), intent(in) :: body
            !! a body with a shape
        real(wp), intent(in) :: x(3)
            !! the point (0 on unused axes) [m]

        real(wp) :: axis(3), t, length2, d(3)

        select case (body%shape)
        case (shape_circle, shape_sphere)
            inside_shape = sum((x - body%centre)**2) <= body%radius**2
        case (shape_cylinder)
            axis = body%axis_end - body%centre
            length2 = sum(axis**2)
            t = dot_product(x - body%centre, axis)/length2
            d = x - body%centre - t*axis
            inside_shape = t >= 0.0_wp .and. t <= 1.0_wp .and. sum(d**2) <= body%radius**2
        case default
            inside_shape = .false.
        end select
    end function inside_shape

    !> Whether a body is a box (every site of its range holds a particle).
    pure logical function is_box(body)
        type(body_spec_type), intent(in) :: body
            !! the body

        is_box = .not. allocated(body%triangle) .and. body%shape == shape_none
    end function is_box

    !> Geometric checks of body `i`: a proper box, inside the domain, holding particles and
    !> sharing no particle site with the bodies before it (two boxes: no common volume).
    subroutine check_body_box(root, dim, domain, particles, count_particles, overlap, bodies, &
            i, error)
        type(cursor_type), intent(in) :: root
            !! top-level object (for messages)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        procedure(body_count_interface) :: count_particles
            !! particles a body holds
        procedure(body_overlap_interface) :: overlap
            !! particle sites two bodies both hold
        type(body_spec_type), intent(inout) :: bodies(:)
            !! bodies 1..i read; body i gets its particle count
        integer, intent(in) :: i
            !! body to check
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: label, corner, what
        real(wp) :: lower(3), upper(3), tol
        integer :: d, j
        integer(i8) :: count, shared

        tol = box_tolerance*domain%dx
        ! listed particles: each checked by the reader; no lattice, no overlap test
        if (allocated(bodies(i)%list)) return
        associate (body => bodies(i))
            label = "bodies["//int_text(i)//'] "'//body%name//'"'
            corner = "corner"
            what = "the box "//fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" [m]"
            if (allocated(body%polygon)) then
                corner = "the bounding box of the polygon, corner"
                what = "the polygon (bounding box "//fmt_box(body%xmin(1:dim), &
                    body%xmax(1:dim))//" [m])"
            else if (body%shape /= shape_none) then
                corner = "the bounding box of the "//trim(shape_names(body%shape))//", corner"
                what = "the "//trim(shape_names(body%shape))//" (bounding box " &
                    //fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" [m])"
            else if (allocated(body%bottom)) then
                corner = "the bounding box of the layer, corner"
                what = "the layer between '"//body%file//"' and '"//body%bottom_file &
                    //"' (bounding box "//fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" [m])"
            else if (allocated(body%triangle)) then
                corner = "the bounding box of the surface '"//body%file//"', corner"
                what = "the closed surface '"//body%file//"' (bounding box " &
                    //fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" [m]"
                if (dim == 2) what = what//", section by z = 0"
                what = what//")"
            end if
            do d = 1, dim
                if (.not. body%xmin(d) < body%xmax(d)) then
                    call root%fail(error, label//": min["//int_text(d)//"] = " &
                        //fmt_real(body%xmin(d))//" must be below max["//int_text(d)//"] = " &
                        //fmt_real(body%xmax(d))//" [m]")
                    return
                end if
            end do
            lower(1:dim) = domain%origin(1:dim)
            upper(1:dim) = domain%origin(1:dim) + domain%ncells(1:dim)*domain%dx
            if (any(body%xmin(1:dim) < lower(1:dim) - tol)) then
                call root%fail(error, label//": "//corner//" min = " &
                    //corner_text(body%xmin(1:dim))//" lies outside the domain " &
                    //fmt_box(lower(1:dim), upper(1:dim), domain_digits)//" [m]")
                return
            end if
            if (any(body%xmax(1:dim) > upper(1:dim) + tol)) then
                call root%fail(error, label//": "//corner//" max = " &
                    //corner_text(body%xmax(1:dim))//" lies outside the domain " &
                    //fmt_box(lower(1:dim), upper(1:dim), domain_digits)//" [m]")
                return
            end if
            count = count_particles(dim, domain, particles, bodies, i)
            if (count < 0) then
                call fatal_error(error, root%src//": "//label//": cannot allocate the memory to " &
                    //"fill the closed surface '"//body%file//"' with particles", exit_other)
                return
            end if
            bodies(i)%particles = count
            if (count == 0) then
                call root%fail(error, label//": "//what//" holds no particle (with ppc = " &
                    //int_text(particles%ppc)//" particles sit at origin + (i + (k - 0.5)/ppc) dx, " &
                    //"k = 1..ppc, in each cell i); make the body larger or raise particles.ppc")
                return
            end if
            do j = 1, i - 1
                if (allocated(bodies(j)%list)) cycle
                associate (other => bodies(j))
                    if (.not. all(min(body%xmax(1:dim), other%xmax(1:dim)) &
                        - max(body%xmin(1:dim), other%xmin(1:dim)) > tol)) cycle
                    if (is_box(body) .and. is_box(other)) then
                        call root%fail(error, label//" overlaps bodies["//int_text(j) &
                            //'] "'//other%name//'": the boxes ' &
                            //fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" and " &
                            //fmt_box(other%xmin(1:dim), other%xmax(1:dim))//" [m] share a " &
                            //"volume; bodies must not overlap")
                        return
                    end if
                    ! a polygon or a surface: their bounding boxes may meet where the bodies
                    ! do not (layers of a slope); the particle sites decide
                    shared = overlap(dim, domain, particles, bodies, i, j)
                    if (shared < 0) then
                        call fatal_error(error, root%src//": "//label//": cannot allocate " &
                            //"the memory to compare its particle sites with those of " &
                            //"bodies["//int_text(j)//"]", exit_other)
                        return
                    else if (shared > 0) then
                        call root%fail(error, label//" overlaps bodies["//int_text(j) &
                            //'] "'//other%name//'": '//int_text(shared)//" particle " &
                            //"sites lie in both (bounding boxes "//fmt_box(body%xmin(1:dim), &
                            body%xmax(1:dim))//" and "//fmt_box(other%xmin(1:dim), &
                            other%xmax(1:dim))//" [m]); bodies must not overlap")
                        return
                    end if
                end associate
            end do
        end associate
    contains

        !> A corner as given, or computed from a shape's centre and radius (without round-off).
        function corner_text(v) result(text)
            real(wp), intent(in) :: v(:)
            character(len=:), allocatable :: text

            if (bodies(i)%shape /= shape_none) then
                text = fmt_vector(v, domain_digits)
            else
                text = fmt_vector(v)
            end if
        end function corner_text

    end subroutine check_body_box

end module mpm_case_bodies
