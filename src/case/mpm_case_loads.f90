!> The `loads` key of a case: the external loads besides gravity, each with its time function.
!>
!> - `"type": "traction"`: a traction [Pa] on the surface of a body whose outward normal is
!>   `surface` ("+y" for the top of a 2D ground), carried by the particles whose centres lie
!>   in the box `min`..`max` at the start. `pressure` pushes into the body (along minus the
!>   normal), `traction` is any vector (shear and normal) added to it. The resultant is the
!>   traction times the loaded area: the box's extent along the surface, clipped to the
!>   extent of those particles (per metre of thickness in 2D); each particle takes a share
!>   proportional to its volume.
!> - `"type": "point"`: a force [N; N/m in 2D] on the particle nearest to `position` at the
!>   start (within one cell), which it follows.
!> - `"type": "body_force"`: an acceleration [m/s2] added to gravity on every particle of
!>   `material` (a seepage force per unit mass, a pseudo-static seismic coefficient times g).
!>
!> `time_function` scales a load in time: `constant` (the default), `ramp` (0 until `start`,
!> linear to 1 over `duration`, then 1) or `table` (times and factors of a CSV `file`,
!> linear between its rows, the first and last factor outside them). A particle carries one
!> traction or point load. The loads do work that the energy balance books as `load_work`.
module mpm_case_loads
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: int_text, fmt_real, fmt_vector
    use mpm_case_cursor, only: cursor_type
    use mpm_case_domain, only: domain_section_type
    use mpm_case_materials, only: material_spec_type, material_index, material_list
    use mpm_time_function, only: time_function_type, read_time_function, time_function_text
    implicit none
    private
    public :: load_spec_type, read_loads, load_keys, load_line, read_box
    public :: load_traction, load_point, load_body_force, load_type_names, surface_names

    integer, parameter :: load_traction = 1, load_point = 2, load_body_force = 3
        !! load types
    character(len=*), parameter :: load_type_names(3) = [character(len=10) :: "traction", &
        "point", "body_force"]
        !! name of each load type in the case file
    character(len=*), parameter :: surface_names(6) = [character(len=2) :: "-x", "+x", "-y", &
        "+y", "-z", "+z"]
        !! outward normals of a traction's surface
    character(len=*), parameter :: load_keys(*) = [character(len=13) :: "type", "name", "min", &
        "max", "surface", "pressure", "traction", "position", "force", "material", &
        "acceleration", "time_function"]
        !! keys of one load

    !> One load of `loads`.
    type :: load_spec_type
        character(len=:), allocatable :: name
            !! name (default "load<i>"), for messages and the summary
        integer :: type = load_traction
            !! load_traction, load_point or load_body_force
        real(wp) :: xmin(3) = 0.0_wp, xmax(3) = 0.0_wp
            !! a traction's box [m]
        integer :: normal_axis = 0, normal_sign = 0
            !! a traction's outward normal: axis and sign
        real(wp) :: vector(3) = 0.0_wp
            !! the load at factor 1: traction [Pa] (pressure included), force [N; N/m in 2D]
            !! or acceleration [m/s2]
        real(wp) :: position(3) = 0.0_wp
            !! a point load's position at the start [m]
        integer :: material = 0
            !! a body force's material index
        type(time_function_type) :: time
            !! its time function
    end type load_spec_type

contains

    !> `loads`: an optional array of loads, each checked against the domain and the
    !> materials.
    subroutine read_loads(root, dim, domain, materials, loads, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        type(load_spec_type), allocatable, intent(out) :: loads(:)
            !! the loads, in file order
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: list, item
        integer :: i

        if (.not. root%has("loads")) then
            allocate (loads(0))
            return
        end if
        call root%get_list("loads", "load", list, error)
        if (allocated(error)) return
        allocate (loads(list%size()))
        do i = 1, size(loads)
            call list%named_item(i, load_keys, "load", item, loads(i)%name, error)
            if (allocated(error)) return
            call item%get_choice("type", load_type_names, [load_traction, load_point, &
                load_body_force], loads(i)%type, error, required=.true.)
            if (allocated(error)) return
            call refuse_other_keys(item, loads(i)%type, error)
            if (allocated(error)) return
            select case (loads(i)%type)
            case (load_traction)
                call read_traction(item, dim, domain, loads(i), error)
            case (load_point)
                call item%get_vector("position", dim, loads(i)%position, error, &
                    required=.true., unit="m")
                if (allocated(error)) return
                if (.not. inside(domain, dim, loads(i)%position)) then
                    call item%fail(error, item%key_path("position")//" = " &
                        //fmt_vector(loads(i)%position(1:dim))//" m is outside the domain " &
                        //domain_text(domain, dim)//"; a point load acts on the particle " &
                        //"nearest to it")
                    return
                end if
                call item%get_vector("force", dim, loads(i)%vector, error, required=.true., &
                    unit=merge("N/m", "N  ", dim == 2))
            case default
                call read_body_force(item, dim, materials, loads(i), error)
            end select
            if (allocated(error)) return
            call read_time_function(item, loads(i)%time, error)
            if (allocated(error)) return
        end do
    end subroutine read_loads

    !> Refuse the keys of the other load types.
    subroutine refuse_other_keys(item, type, error)
        type(cursor_type), intent(in) :: item
            !! the load's object
        integer, intent(in) :: type
            !! its type
        type(error_type), allocatable, intent(out) :: error
            !! set on a key of another type

        character(len=13), parameter :: own(8) = [character(len=13) :: "min", "max", &
            "surface", "pressure", "traction", "position", "force", "material"]
        integer, parameter :: owner(8) = [load_traction, load_traction, load_traction, &
            load_traction, load_traction, load_point, load_point, load_body_force]
        integer :: k

        do k = 1, size(own)
            if (owner(k) /= type .and. item%has(trim(own(k)))) then
                call item%fail(error, item%key_path(trim(own(k)))//" only applies to a load " &
                    //'of type "'//trim(load_type_names(owner(k)))//'"; remove it')
                return
            end if
        end do
        if (type /= load_body_force .and. item%has("acceleration")) then
            call item%fail(error, item%key_path("acceleration")//" only applies to a load " &
                //'of type "body_force"; remove it')
        end if
    end subroutine refuse_other_keys

    !> A traction: its box inside the domain, its surface and the traction.
    subroutine read_traction(item, dim, domain, load, error)
        type(cursor_type), intent(in) :: item
            !! the load's object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(load_spec_type), intent(inout) :: load
            !! the load
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        integer :: surface, k
        real(wp) :: pressure

        call read_box(item, dim, domain, load%xmin, load%xmax, error)
        if (allocated(error)) return
        surface = 0
        call item%get_choice("surface", surface_names(1:2*dim), [(k_code(surface_names(k)), &
            k=1, 2*dim)], surface, error, required=.true.)
        if (allocated(error)) return
        load%normal_axis = abs(surface)
        load%normal_sign = sign(1, surface)
        if (.not. (item%has("pressure") .or. item%has("traction"))) then
            call item%fail(error, item%path//": a traction needs 'pressure' (Pa, pushing " &
                //"into the body) or 'traction' (a vector, Pa), or both; none was given")
            return
        end if
        call item%get_vector("traction", dim, load%vector, error, unit="Pa")
        if (allocated(error)) return
        pressure = 0.0_wp
        call item%get_real("pressure", pressure, error)
        if (allocated(error)) return
        load%vector(load%normal_axis) = load%vector(load%normal_axis) - &
            real(load%normal_sign, wp)*pressure
    contains
        !> The code of a surface name: the axis, signed by the direction.
        pure integer function k_code(name)
            character(len=*), intent(in) :: name
            k_code = index("xyz", name(2:2))
            if (name(1:1) == "-") k_code = -k_code
        end function k_code
    end subroutine read_traction

    !> A box `min`, `max` of an object: not empty, inside the domain.
    subroutine read_box(item, dim, domain, xmin, xmax, error)
        type(cursor_type), intent(in) :: item
            !! the object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        real(wp), intent(inout) :: xmin(3), xmax(3)
            !! the corners [m]
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        real(wp) :: upper(3)

        call item%get_vector("min", dim, xmin, error, required=.true., unit="m")
        if (allocated(error)) return
        call item%get_vector("max", dim, xmax, error, required=.true., unit="m")
        if (allocated(error)) return
        if (any(xmax(1:dim) <= xmin(1:dim))) then
            call item%fail(error, item%path//": the box min = "//fmt_vector(xmin(1:dim)) &
                //" m, max = "//fmt_vector(xmax(1:dim))//" m is empty; max must exceed " &
                //"min on every axis")
            return
        end if
        upper = domain%origin + real(domain%ncells, wp)*domain%dx
        if (any(xmin(1:dim) < domain%origin(1:dim)) .or. any(xmax(1:dim) > upper(1:dim))) then
            call item%fail(error, item%path//": the box min = "//fmt_vector(xmin(1:dim)) &
                //" m, max = "//fmt_vector(xmax(1:dim))//" m is not inside the domain " &
                //domain_text(domain, dim))
        end if
    end subroutine read_box

    !> A body force: its material and acceleration.
    subroutine read_body_force(item, dim, materials, load, error)
        type(cursor_type), intent(in) :: item
            !! the load's object
        integer, intent(in) :: dim
            !! number of space dimensions
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        type(load_spec_type), intent(inout) :: load
            !! the load
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: material

        material = ""
        call item%get_string("material", material, error, required=.true.)
        if (allocated(error)) return
        load%material = material_index(materials, material)
        if (load%material == 0) then
            call item%fail(error, item%key_path("material")//' = "'//material//'" is not ' &
                //"a material of this case; the materials are: "//material_list(materials))
            return
        end if
        call item%get_vector("acceleration", dim, load%vector, error, required=.true., &
            unit="m/s2")
    end subroutine read_body_force

    !> One line of the --check summary for a load: its name, type, value and time function.
    pure function load_line(load, dim, materials) result(line)
        type(load_spec_type), intent(in) :: load
            !! the load
        integer, intent(in) :: dim
            !! number of space dimensions
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials
        character(len=:), allocatable :: line

        line = load%name//": "//trim(load_type_names(load%type))
        select case (load%type)
        case (load_traction)
            line = line//" "//fmt_vector(load%vector(1:dim))//" Pa on the particles of " &
                //fmt_vector(load%xmin(1:dim))//" - "//fmt_vector(load%xmax(1:dim)) &
                //" m, surface "//trim(merge("+", "-", load%normal_sign > 0)) &
                //"xyz"(load%normal_axis:load%normal_axis)
        case (load_point)
            line = line//" "//fmt_vector(load%vector(1:dim))//merge(" N/m", " N  ", dim == 2) &
                //" at "//fmt_vector(load%position(1:dim))//" m"
        case default
            line = line//" "//fmt_vector(load%vector(1:dim))//' m/s2 on material "' &
                //materials(load%material)%name//'"'
        end select
        line = trim(line)//", "//time_function_text(load%time)
    end function load_line

    !> Whether a point lies in the domain (its faces included).
    pure logical function inside(domain, dim, x)
        type(domain_section_type), intent(in) :: domain
        integer, intent(in) :: dim
        real(wp), intent(in) :: x(3)

        real(wp) :: upper(3)

        upper = domain%origin + real(domain%ncells, wp)*domain%dx
        inside = all(x(1:dim) >= domain%origin(1:dim) .and. x(1:dim) <= upper(1:dim))
    end function inside

    !> The domain's extent, for messages: "from (x0, y0) to (x1, y1) m".
    pure function domain_text(domain, dim) result(text)
        type(domain_section_type), intent(in) :: domain
        integer, intent(in) :: dim
        character(len=:), allocatable :: text

        text = "from "//fmt_vector(domain%origin(1:dim))//" to " &
            //fmt_vector(domain%origin(1:dim) + real(domain%ncells(1:dim), wp)*domain%dx) &
            //" m"
    end function domain_text

end module mpm_case_loads
